"""Real-IKEA: physically faithful articulated-object assets and learning stack."""

import os

# Headless CPU rendering (Mesa's OSMesa) unless the user chose another MuJoCo GL backend.
os.environ.setdefault("MUJOCO_GL", "osmesa")
