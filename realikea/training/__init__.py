"""Training: rsl-rl PPO on the env pool, configured by Hydra."""
