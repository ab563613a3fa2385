"""The robot's web dashboard: a Starlette server streaming node states and sensor data to browsers over SSE."""
