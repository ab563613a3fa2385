"""MuJoCo simulation engine used in MODE_SIMULATION."""
