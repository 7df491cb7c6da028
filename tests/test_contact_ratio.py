"""Contact ratio of the reference samples (Fig. 4.21) with the dry/wet model's real contact."""

import numpy as np
import pytest

from friction_model import element_real_contact_fractions
from friction_model.contact.drywet import DryWetParameters, real_contact_fraction
from friction_model.dynamics.contact import face_real_contact_fraction, reference_contact_ratios


def test_face_real_contact_of_uniform_and_triangular_pressure():
    p = DryWetParameters()
    A = 4.55e-3 * 80e-3
    # full contact: uniform pressure F / A, the dry/wet model's fraction exactly
    F = 2.5e5 * A
    assert face_real_contact_fraction(F, 1.0, A, p) == pytest.approx(
        real_contact_fraction(2.5e5, p), rel=1e-14
    )
    # lifted-off face (c = 0.5): triangular pressure, mean F / (c A); analytic integral
    # c phi_ref (2 p_mean / p_ref)^gamma / (1 + gamma) while below the clip at 1
    c, F = 0.5, 0.5e5 * A
    p_mean = F / (c * A)
    g = p.contact_pressure_exponent
    exact = c * p.contact_fraction_ref * (2 * p_mean / p.contact_pressure_ref_Pa) ** g / (1 + g)
    # midpoint rule on s^gamma with 64 points: relative error 3.6e-4
    assert face_real_contact_fraction(F, c, A, p) == pytest.approx(exact, rel=1e-3)
    assert face_real_contact_fraction(0.0, 1.0, A, p) == 0.0


# three steady block simulations (13 s): with -m slow; the default run holds Fig. 4.21's
# ratios through the renderer's model (test_footage_real.test_patchy_contact_ratio_follows_the_
# model_and_falls_from_g0_to_g7)
@pytest.mark.slow
def test_contact_ratio_of_g0_and_g7_matches_fig_4_21():
    # Fig. 4.21: about 70 % (G0) and 25 % (G7), read from the figure (+-0.05 is the required
    # accuracy and about the reading accuracy). Predicted: nothing here is fitted to Fig. 4.21
    # (the real-contact law comes from Table 4.6, the rubber from Shore A 60).
    table = reference_contact_ratios(("G0", "G3", "G7"), t_end_s=0.02)
    ratios = table["contact_ratio"].to_numpy()
    assert ratios[0] == pytest.approx(0.70, abs=0.05)
    assert ratios[-1] == pytest.approx(0.25, abs=0.05)
    assert np.all(np.diff(ratios) < 0)  # falls with the number of sipes
    assert np.all(np.diff(table["angle_deg"].to_numpy()) > 0)  # thinner elements tilt more
    # the real contact is a fraction of the touching area
    assert np.all(table["contact_ratio"] < table["apparent_contact_ratio"])


@pytest.mark.slow
@pytest.mark.parametrize("preset", ["G0", "G7"])
def test_element_real_contact_fractions_for_the_renderer(preset):
    # What the renderer draws, element by element: weighted by the element lengths it must
    # give the sample's contact ratio, which Fig. 4.21 gives to +-0.05 (about 0.70 for G0,
    # 0.25 for G7; predicted, nothing fitted to Fig. 4.21).
    from friction_model import reference_block

    geom = reference_block(preset)
    a = element_real_contact_fractions(preset, 1.0, 2.5)
    assert a.shape == (geom.n_elements,)
    assert np.all((a > 0) & (a <= 1))
    ratio = float(np.sum(a * geom.element_lengths) / geom.length_mm)
    assert ratio == pytest.approx({"G0": 0.70, "G7": 0.25}[preset], abs=0.05)
    a[0] = -1.0  # a copy: the cache is not changed
    assert element_real_contact_fractions(preset, 1.0, 2.5)[0] > 0


def test_a_reference_sample_may_be_given_by_its_block():
    # before: "unknown reference sample 'BlockGeometry(length_mm=20.0, ...)'" (helper-12)
    from friction_model import BlockGeometry, reference_block

    by_name = element_real_contact_fractions("G3", 1.0, 2.5)
    assert np.array_equal(element_real_contact_fractions(reference_block("G3"), 1.0, 2.5),
                          by_name)
    with pytest.raises(ValueError, match=r"preset must be a reference sample .* another block"):
        element_real_contact_fractions(BlockGeometry(n_sipes=2), 1.0, 2.5)


def test_step_element_takes_a_reference_sample_by_name():
    # before: TypeError "geometry must be a BlockGeometry, got str" (helper-12)
    from friction_model import reference_block, step_element

    assert step_element(geometry="G3") == step_element(geometry=reference_block("G3"))
