"""Vectorized env pool (the only code that knows about processes), rsl-rl and gymnasium adapters."""
