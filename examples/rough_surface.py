"""Fig. 5.6: the siped block crosses a rough surface twice.

The thesis transformed a measured concrete profile into a preload distance y0(t) and let the
block pass it twice: "the single block elements become deflected one after another by the
first bump. The second deflection of the single elements by the same bump is slightly
higher due to the system dynamics." The measured profile is not available; a synthetic
one stands in for it: 14 asperities (Gaussian bumps, 0.3-1.5 mm wide, up to 0.15 mm high,
seeded) on a 40 mm track, repeated once. Every element meets the profile later by its
distance behind the leading element (:func:`element_surface_profiles`).

The "system dynamics" here: the block starts sliding at t = 0 with the friction
coefficient building up from zero with the time constant of Eq. 5.12 (tau = 4 ms, the
thesis's model of the transient friction), so on the first pass the elements meet the
bumps while the friction and the deflection still grow; on the second pass they arrive in
steady sliding and are deflected further by the same bumps.

Scenario as in ``tests/test_rigid.py`` (face contact, c_N = 5e4 N/m, Eq. 5.7 with a1 = 0.2,
a2 = 0.15, a3 = -0.3 s/m), with the one rubber's loss factor (0.2; the test uses 0.4),
v0 = 5 m/s, y0 = 5.1 mm.

Run: ``python examples/rough_surface.py [--out DIR]``; writes
``examples/out/rough_surface/rough_surface.png`` and ``rough_surface.csv``.
"""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
from _common import example_arguments, face_contact_block, save_figure

from friction_model.contact.laws import RelaxedFriction
from friction_model.dynamics import SolverOptions
from friction_model.dynamics.rigid import (
    element_surface_profiles,
    simulate_block_dynamics,
)

out = example_arguments(None, __doc__, "rough_surface").out

V0, Y0, TAU = 5.0, 5.1e-3, 0.004
TRACK = 0.04  # length of one pass of the profile, m
params, law = face_contact_block()

rng = np.random.default_rng(56)
s = np.linspace(0.0, TRACK, 1601)
z = np.zeros_like(s)
for centre, width, height in zip(
    rng.uniform(0.005, TRACK - 0.005, 14),
    rng.uniform(0.3e-3, 1.5e-3, 14),
    rng.uniform(0.03e-3, 0.15e-3, 14),
    strict=True,
):
    z += height * np.exp(-0.5 * ((s - centre) / width) ** 2)
heights = np.concatenate([z, z[1:]])  # passed twice
positions = np.concatenate([s, s[1:] + TRACK])

offsets = params.element_offsets_m
t_end = (2 * TRACK + offsets[-1]) / V0
profiles = element_surface_profiles(params, Y0, heights, positions, lambda t: V0, t_max_s=t_end)
res = simulate_block_dynamics(
    params,
    velocity=V0,
    preload=profiles,
    friction=RelaxedFriction(law, tau_s=TAU),
    initial_mu=0.0,
    t_end_s=t_end,
    solver=SolverOptions(max_step_s=2e-5),
    output_step_s=2e-5,
)
print(f"{res.meta['nfev']} rhs evaluations, {res.meta['runtime_s']:.1f} s")
for element, off in enumerate(offsets):
    g = res.data[res.data.element == element]
    peaks = []
    for k in (0, 1):
        t0, t1 = (k * TRACK + off) / V0, ((k + 1) * TRACK + off) / V0
        peaks.append(g[(g.time_s >= t0) & (g.time_s < t1)]["angle_deg"].max())
    print(
        f"element {element}: peak deflection {peaks[0]:.2f} deg on the first pass, "
        f"{peaks[1]:.2f} deg on the second"
    )

fig, (ax, ax_z) = plt.subplots(
    2, 1, figsize=(7.5, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
)
res.plot("angle_deg", ax=ax)
ax.set_title("Siped block crossing a rough surface twice (cp. Fig. 5.6)")
for k in (1, 2):
    ax.axvline(k * TRACK / V0, color="0.6", lw=0.8, ls="--")
t = res.data[res.data.element == 0]["time_s"].to_numpy()
ax_z.plot(t, np.interp(t * V0, positions, heights) * 1e3, color="0.3")
ax_z.set_ylabel("z (leading element) / mm")
ax_z.set_xlabel("time / s")
save_figure(fig, out / "rough_surface.png")
res.data.to_csv(out / "rough_surface.csv", index=False)
print(f"wrote {out}")
