"""Helpers shared by the test suites and benchmarks: compiled node settings, node processes, an in-process ROS
client, the joshuac command, and stand-ins for devices that live in another process (a Pybricks hub emulator,
a network camera)."""
