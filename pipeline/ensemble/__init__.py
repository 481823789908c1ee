"""Ensembles: a member's seeds, the members' aggregate and its table (docs/ensemble.md)."""
