"""Export built configurations to other simulators' formats: URDF, USD and a copy of the MJCF."""

FORMATS = ("urdf", "usd", "mjcf")  # the exporters of export/driver.py, by the name the CLI takes
