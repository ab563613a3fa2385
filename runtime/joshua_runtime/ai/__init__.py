"""LeRobot policy inference, dataset recording and the local model registry."""
