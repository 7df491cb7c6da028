"""Plot helpers of SimulationResult draw what the data says."""

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest

from friction_model.dynamics import SimulationResult


def make_result():
    t = np.linspace(0, 0.01, 11)
    x = np.linspace(0, 6e-3, 7)
    r = np.outer(t / t[-1], (x / x[-1]) ** 2) * 1.6e-3
    data = pd.DataFrame({"time_s": np.repeat(t, 2), "element": np.tile([0, 1], 11)})
    data["angle_deg"] = np.where(data["element"] == 0, 5.0, 7.0)
    return SimulationResult(data=data, fields={"x_m": x, "t_s": t, "r_m": r}, meta={"model": "m"})


def test_plot_lines_follow_the_data():
    res = make_result()
    fig = res.plot()
    lines = fig.axes[0].get_lines()
    assert [line.get_ydata()[0] for line in lines] == [5.0, 7.0]
    assert res.steady().to_dict() == {0: 5.0, 1: 7.0}


def test_plot_shapes_draws_the_tip_deflection():
    fig = make_result().plot_shapes([0.01])
    line = fig.axes[0].get_lines()[0]
    assert line.get_xdata()[-1] == pytest.approx(1.6)  # mm at the tip, last time
    assert line.get_ydata()[-1] == pytest.approx(6.0)


def test_plot_shapes_needs_fields():
    res = SimulationResult(data=pd.DataFrame({"time_s": [0.0], "element": [0]}))
    with pytest.raises(ValueError, match="x_m"):
        res.plot_shapes()
