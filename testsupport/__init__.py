"""Helpers shared by the test suites: compiled node settings, node processes, an in-process ROS client
and the joshuac command."""
