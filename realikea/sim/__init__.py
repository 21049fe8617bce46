"""Robot model, scene building and IK controller (see realikea/sim/README.md)."""
