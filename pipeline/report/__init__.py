"""The report: merged metrics, figures and report.md of one results directory (README.md)."""
