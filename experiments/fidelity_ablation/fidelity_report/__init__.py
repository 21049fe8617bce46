"""The fidelity-ablation report: every finished run (a directory holding `.hydra/config.yaml`,
`eval.json` and `metrics.csv`) under the given roots, aggregated into report.md and plots
(`python experiments/fidelity_ablation/report.py`, whose help says what it writes)."""
