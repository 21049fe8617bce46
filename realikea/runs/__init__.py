"""Training runs on disk: finished runs' records and training curves, and the committed
checkpoints (what each is, what made it, who cites it)."""
