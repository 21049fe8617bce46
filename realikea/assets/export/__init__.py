"""Export built configurations to other simulators' formats: URDF, USD and a copy of the MJCF."""
