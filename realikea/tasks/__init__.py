"""The open-articulation task: rewards, observations, terminations, randomization, outcome."""
