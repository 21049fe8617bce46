"""Policies: one interface for learned, scripted, sampled and teleoperated control."""
