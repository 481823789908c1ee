"""make validate: the engine and the detectors against references (README.md)."""
