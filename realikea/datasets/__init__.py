"""Datasets the project writes for other tools (LeRobot)."""
