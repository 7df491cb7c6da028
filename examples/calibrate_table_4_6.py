"""Calibrate ONE shared parameter set of the dry/wet model on Table 4.6 of the thesis.

The four measured G3 characteristics (cold/dry and warm/humid at 2.5 and 5 bar, 1..7 m/s)
differ only in temperature, humidity and pressure; every model parameter is shared.
Run: ``python examples/calibrate_table_4_6.py [--out DIR]`` (about a minute); writes the fitted
parameters (JSON), the comparison table (CSV) and a plot to ``examples/out/table_4_6/``.
"""

import json

import matplotlib

matplotlib.use("Agg")

from _common import example_arguments

from friction_model import DryWetParameters, calibrate_table_4_6, evaluate_on_table_4_6
from friction_model.plots import plot_table_4_6

out = example_arguments(None, __doc__, "table_4_6").out

_, rmse_default = evaluate_on_table_4_6(DryWetParameters())
result = calibrate_table_4_6(n_starts=4, rng=5)
print(result.summary())
shipped = {k: round(v, 4) for k, v in rmse_default.items()}
print("\nRMSE of the shipped default parameters:", shipped)
print("\nModel vs. Table 4.6:")
print(result.table.round(4).to_string(index=False))

result.table.to_csv(out / "table_4_6_model.csv", index=False)
(out / "calibrated_parameters.json").write_text(json.dumps(result.params.to_dict(), indent=2))
plot_table_4_6(result.table, result.rmse).savefig(out / "table_4_6_model.png", dpi=130)
print(f"wrote {out}")
