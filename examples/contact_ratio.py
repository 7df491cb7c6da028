"""Contact ratio of the reference samples G0-G7 from the block dynamics (Fig. 4.21).

The touching part of each element face (rigid block model, the one rubber) times the real
contact fraction of the dry/wet model at the local pressure
(:func:`friction_model.contact.drywet.real_contact_fraction`, the function the synthetic renderer
uses too). Predicted, not fitted: compare G0 and G7 with the thesis's ~0.70 and ~0.25.

Run: ``python examples/contact_ratio.py [--out DIR]`` (about 25 s); writes a CSV and a bar chart to
``examples/out/contact_ratio/``.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from _common import example_arguments, save_figure

from friction_model.dynamics import reference_contact_ratios

out = example_arguments(None, __doc__, "contact_ratio").out

table = reference_contact_ratios()
table.to_csv(out / "contact_ratio.csv", index=False)
print(table.round(3).to_string(index=False))

fig, ax = plt.subplots(figsize=(6, 3.8))
ax.bar(table["sample"], table["apparent_contact_ratio"], color="0.85", label="touching faces")
ax.bar(table["sample"], table["contact_ratio"], color="0.5", label="real contact (1 m/s, 2.5 bar)")
ax.plot(table["sample"], table["thesis_contact_ratio"], "o", color="C3", label="thesis, Fig. 4.21")
ax.set(ylabel="real contact area / nominal area", ylim=(0, 1.05))
ax.legend()
save_figure(fig, out / "contact_ratio.png")
print(f"wrote {out}")
