"""Contact ratio of the reference samples falls with the number of sipes (Fig. 4.21)."""

import numpy as np

from friction_model.dynamics.contact import reference_contact_ratios


def test_contact_ratio_falls_with_the_number_of_sipes():
    # Thesis (Fig. 4.21): about 70 % for G0, 25 % for G7, falling with the sipes. The model
    # has no ice waviness, so its level is higher; the ordering is what it must get right.
    table = reference_contact_ratios(("G0", "G3", "G7"), t_end_s=0.02)
    ratios = table["contact_ratio"].to_numpy()
    assert np.all(np.diff(ratios) < 0)
    assert np.all(np.diff(table["angle_deg"].to_numpy()) > 0)  # thinner elements tilt more
    g0, g7 = ratios[0], ratios[-1]
    assert g7 / g0 < 0.5  # thesis: 0.25 / 0.70 = 0.36; model about 0.36
    assert np.all((ratios > 0) & (ratios <= 1))
