"""The parametric study: its plan (Make rules) and its report (docs/params.md)."""
