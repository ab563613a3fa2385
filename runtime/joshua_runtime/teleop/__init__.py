"""Teleoperation of a mobile base: Twist from a keyboard in a terminal or from a gamepad's Joy messages."""
