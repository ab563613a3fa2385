"""LeRobot datasets on disk: what they hold, and new datasets made from them or from bags (joshua-dataset)."""
