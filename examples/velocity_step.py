"""Fig. 5.7: the siped block answers a velocity step, with and without Eq. 5.12.

A G3 block (4 elements of 4.55 mm x 6 mm, two-mass oscillators) slides at v1 = 1 m/s and is
accelerated to v2 = 5 m/s at t1 = 0.2 s (within 20 ms). The decreasing characteristic
(Eq. 5.7) lowers the friction and with it the deflection angles. With the time dependence
of the friction coefficient (Eq. 5.12, tau = 30 ms) the angles follow the new level with
that lag; without it they drop within the ~1 ms of the element dynamics.

Scenario (as in ``tests/test_rigid.py``, but with the one rubber): penalty springs spread
over the bottom face ("face" contact), c_N = 5e4 N/m so that y0 = 5.1 mm gives 45 N per
element (1.2 bar), the one rubber's loss factor (friction_model.compound, 0.2; the test
uses 0.4), Eq. 5.7 with a1 = 0.2, a2 = 0.15, a3 = -0.3 s/m.

Run: ``python examples/velocity_step.py [--out DIR]``; writes
``examples/out/velocity_step/velocity_step.png`` and ``velocity_step.csv``.
"""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pandas as pd
from _common import example_arguments, face_contact_block, save_figure

from friction_model.contact.laws import RelaxedFriction
from friction_model.dynamics import velocity_step
from friction_model.dynamics.rigid import simulate_block_dynamics

out = example_arguments(None, __doc__, "velocity_step").out

T_STEP, TAU, T_END = 0.2, 0.03, 0.4
params, law = face_contact_block()
velocity = velocity_step(1.0, 5.0, T_STEP, rise_s=0.02)
runs = {
    "steady friction (no Eq. 5.12)": law,
    f"Eq. 5.12, tau = {TAU * 1e3:.0f} ms": RelaxedFriction(law, tau_s=TAU),
}

fig, axes = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
tables = []
for ax, (label, friction) in zip(axes, runs.items(), strict=True):
    res = simulate_block_dynamics(
        params,
        velocity=velocity,
        preload=5.1e-3,
        friction=friction,
        t_end_s=T_END,
        output_step_s=5e-4,
    )
    res.plot("angle_deg", ax=ax)
    ax.set_title(label)
    ax.axvline(T_STEP, color="0.6", lw=0.8, ls="--")
    twin = ax.twinx()
    d0 = res.data[res.data.element == 0]
    twin.plot(d0["time_s"], d0["v0_mps"], color="0.5", lw=0.8)
    twin.set_ylabel("v0 / (m/s)", color="0.5")
    print(f"{label}: ({res.meta['nfev']} rhs evaluations, {res.meta['runtime_s']:.1f} s)")
    for element, g in res.data.groupby("element"):
        before = g[(g.time_s > T_STEP - 0.02) & (g.time_s < T_STEP)]["angle_deg"].mean()
        after = g[g.time_s > T_END - 0.02]["angle_deg"].mean()
        target = before + 0.632 * (after - before)
        later = g[g.time_s > T_STEP]
        t63 = later.time_s[later.angle_deg <= target].min() - T_STEP
        print(
            f"  element {element}: {before:6.2f} deg at 1 m/s -> {after:6.2f} deg at 5 m/s, "
            f"63 % of the change after {t63 * 1e3:5.1f} ms"
        )
    tables.append(res.data.assign(run=label))
axes[-1].set_xlabel("time / s")
fig.suptitle("Velocity step 1 -> 5 m/s at 0.2 s (cp. Fig. 5.7)")
save_figure(fig, out / "velocity_step.png")
pd.concat(tables).to_csv(out / "velocity_step.csv", index=False)
print(f"wrote {out}")
