"""The one exception type for bad user input: its message names the input and what to do."""


class RealIkeaError(Exception):
    """A user-facing error (bad path, bad mesh, unknown id or config value)."""
