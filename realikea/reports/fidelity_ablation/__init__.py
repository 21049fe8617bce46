"""Finished training runs on disk: their config, evaluation, training metrics and wall time."""
