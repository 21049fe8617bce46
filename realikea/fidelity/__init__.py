"""Collision fidelity: bidirectional surface deviation between visual and collision shells."""
