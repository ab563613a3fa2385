"""`joshua-desktop`: a Qt6 panel to drive, watch and calibrate a servo bus or a running robot."""
