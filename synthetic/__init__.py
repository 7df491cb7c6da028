"""Synthetic data with exact ground truth: test-rig runs now, footage in later releases."""

__all__: list[str] = []
