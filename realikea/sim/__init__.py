"""Robot model, scene building and IK controller (see docs/task.md)."""
