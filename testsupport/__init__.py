"""Helpers shared by the test suites: compiled node settings, node processes and the joshuac command."""
