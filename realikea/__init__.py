"""Real-IKEA: physically faithful articulated-object assets and learning stack."""
