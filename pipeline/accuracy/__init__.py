"""The accuracy sweep: its plan (Make rules) and its table (README.md, docs/accuracy.md)."""
