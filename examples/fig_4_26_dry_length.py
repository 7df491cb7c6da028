"""Reproduce Fig. 4.26: the dry run-in length of Eq. 4.7 over v, p, dT and mu_dry.

Run: ``python examples/fig_4_26_dry_length.py [--out DIR]``; writes PNG and CSV to
``examples/out/fig_4_26/``.
"""

import matplotlib

matplotlib.use("Agg")

from _common import example_arguments

from friction_model import dry_run_in_length
from friction_model.plots import fig_4_26_table, plot_fig_4_26

out = example_arguments(None, __doc__, "fig_4_26").out

table = fig_4_26_table()
table.to_csv(out / "dry_length.csv", index=False)
plot_fig_4_26(table).savefig(out / "fig_4_26_dry_length.png", dpi=130)

eps = dry_run_in_length(8.0, 0.25e6, 1.5, 1.0)
print(f"Thesis example (dT = 8 K, 2.5 bar, mu_dry = 1.5, 1 m/s): epsilon = {eps * 1e3:.2f} mm")
at_1 = table[(table["mu_dry"] == 1.5) & (table["velocity_mps"] == table["velocity_mps"].min())]
print(at_1.round(3).to_string(index=False))
print(f"wrote {out}")
