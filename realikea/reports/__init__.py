"""Reports over experiment outputs: the logic behind the thin scripts under experiments/."""
