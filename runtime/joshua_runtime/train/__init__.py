"""Training and evaluation of SO-100 behaviours in simulation: gymnasium tasks, PPO, LeRobot imitation."""
