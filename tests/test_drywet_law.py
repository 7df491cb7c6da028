"""The dry/wet model as a tabulated friction law for the dynamics."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from friction_model import Conditions, reference_block
from friction_model.contact.drywet import element_friction_table, friction_table
from friction_model.contact.drywet_law import DryWetLaw

G3 = reference_block("G3")


@pytest.fixture(scope="module")
def law():
    return DryWetLaw(G3, temperature_C=-5.0, humidity_pct=40.0)


def random_points(n=200, seed=0):
    rng = np.random.default_rng(seed)
    v = np.exp(rng.uniform(np.log(0.05), np.log(20.0), n))
    p = np.exp(rng.uniform(np.log(3e4), np.log(9e5), n))
    return v, p


def test_law_matches_model_within_interpolation_error(law):
    # Independent truth: the model evaluated directly at random (v, p) off the table grid.
    # Linear interpolation in log v, log p on 96 x 24 nodes: stated error 1.5 % of mu
    # (largest where mu bends sharply at low v and p).
    v, p = random_points()
    conds = [Conditions(a, b, -5.0, humidity_pct=40.0) for a, b in zip(v, p, strict=True)]
    ref = friction_table(G3, conds)
    assert_allclose(law(v, pressure_Pa=p), ref["mu"], rtol=1.5e-2)


def test_per_element_law_and_preheating():
    v, p = random_points(10, seed=1)
    laws = [DryWetLaw(G3, temperature_C=-5.0, humidity_pct=40.0, element=i) for i in (0, 3)]
    conds = [Conditions(a, b, -5.0, humidity_pct=40.0) for a, b in zip(v, p, strict=True)]
    ref = element_friction_table(G3, conds)
    assert_allclose(laws[0](v, pressure_Pa=p), ref[:, 0], rtol=1.5e-2)
    assert_allclose(laws[1](v, pressure_Pa=p), ref[:, 3], rtol=1.5e-2)
    # Fig. 4.25: the preheated last element has less friction than the leading one, unless
    # the leading one is fully dry (mu = mu_dry = 1.5: nothing melts, both are dry)
    lead, last = laws[0](v, pressure_Pa=p), laws[1](v, pressure_Pa=p)
    melting = lead < 1.5 - 1e-9
    assert np.all(last[melting] < lead[melting]) and np.all(last <= lead + 1e-12)


def test_even_in_v_and_scalar_in_scalar_out(law):
    assert isinstance(law(1.0), float)
    assert law(-2.0) == law(2.0)


def test_bad_input(law):
    with pytest.raises(ValueError, match="element"):
        DryWetLaw(G3, temperature_C=-5.0, element=4)
    with pytest.raises(ValueError, match="temperature_C"):
        law(1.0, temperature_C=-3.0)


def test_scalar_fast_path_equals_array_path(law):
    v, p = random_points(20, seed=3)
    scalar = [law(a, pressure_Pa=b) for a, b in zip(v, p, strict=True)]
    assert_allclose(scalar, law(v, pressure_Pa=p), rtol=1e-12)
    assert law(2.0) == pytest.approx(float(law(np.array([2.0]))[0]), rel=1e-12)
