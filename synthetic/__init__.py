"""Synthetic data with exact ground truth: test-rig runs now, footage in later releases."""

from synthetic.rig import RUN_COLUMNS, make_raw_run, write_run_csv

__all__ = ["RUN_COLUMNS", "make_raw_run", "write_run_csv"]
