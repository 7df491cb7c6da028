"""Parameter sweeps: every scheduler gives the same table; failures keep their row."""

import importlib.util

import pandas as pd
import pytest
from pandas.testing import assert_frame_equal

from friction_model import Conditions, friction_table, reference_block
from friction_model.dynamics.sweep import dry_wet_point, parameter_grid, run_sweep

GRID = parameter_grid(velocity_mps=[1.0, 3.0, 7.0], temperature_C=[-5.0, -1.0])


def direct_mu(grid: pd.DataFrame) -> list[float]:
    pairs = zip(grid.velocity_mps, grid.temperature_C, strict=True)
    conds = [Conditions.from_bar(v, 2.5, t) for v, t in pairs]
    return friction_table(reference_block("G3"), conds)["mu"].tolist()


def test_serial_sweep_equals_direct_model():
    table = run_sweep(dry_wet_point, GRID, scheduler="serial", progress=False)
    assert list(table.columns[:2]) == ["velocity_mps", "temperature_C"]
    assert table["error"].eq("").all()
    assert table["mu"].tolist() == pytest.approx(direct_mu(GRID), rel=1e-12)


def test_process_pool_gives_the_same_table():
    serial = run_sweep(dry_wet_point, GRID, scheduler="serial", progress=False)
    pool = run_sweep(dry_wet_point, GRID, scheduler="processes", workers=2, progress=False)
    assert_frame_equal(serial, pool)


# a local dask cluster's start (about 3 s): with -m slow, which CI runs with every extra; the
# default run holds the dask scheduler through analyze (test_analyze.test_batch_on_a_dask_
# scheduler) and the sweep through a process pool (above)
@pytest.mark.slow
@pytest.mark.skipif(importlib.util.find_spec("distributed") is None, reason="needs dask extra")
def test_dask_local_cluster_gives_the_same_table():
    serial = run_sweep(dry_wet_point, GRID.head(2), scheduler="serial", progress=False)
    dask = run_sweep(dry_wet_point, GRID.head(2), scheduler="dask", workers=1, progress=False)
    assert_frame_equal(serial, dask)


def test_a_failing_set_keeps_its_row_and_the_others():
    grid = pd.DataFrame({"velocity_mps": [1.0, 2.0, 3.0], "temperature_C": [-5.0, 3.0, -5.0]})
    table = run_sweep(dry_wet_point, grid, scheduler="processes", workers=2, progress=False)
    assert table["error"].iloc[1].startswith("ValueError") and "temperature_C" in table["error"][1]
    assert table["error"].iloc[[0, 2]].eq("").all()
    assert table["mu"].iloc[[0, 2]].notna().all()


def test_bad_scheduler_arguments():
    with pytest.raises(ValueError, match="workers"):
        run_sweep(dry_wet_point, GRID, workers=-1)
