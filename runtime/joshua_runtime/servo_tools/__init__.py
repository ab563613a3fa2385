"""Tools for STS3215 servo buses: scan, ids, baud rates, status, port finding, calibration, health and goal guards."""
