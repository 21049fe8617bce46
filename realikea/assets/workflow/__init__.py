"""The six stages of the paper's dataset construction workflow, one module per step."""
