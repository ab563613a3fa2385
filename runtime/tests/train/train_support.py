"""Settings of the PPO run the training tests share (trained once per session, see conftest.py)."""

LEARNING_STEPS = 30_000
LEARNING_SEED = 7
LEARNING_ENVS = 16
EVALUATION_EPISODES = 40
