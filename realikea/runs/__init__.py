"""Committed training runs as records: what each kept checkpoint is, what made it, who cites it."""
