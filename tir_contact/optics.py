"""The darkness of full contact from the rig's optics: Fresnel reflection at contact.

Where rubber touches the surface the prism's light meets the rubber instead of air and
is no longer totally reflected: what comes back is the Fresnel reflection at the
substrate/rubber interface, and full contact's darkness is ``1 - R`` (unpolarised light,
``R = (R_s + R_p) / 2``; Born & Wolf, *Principles of Optics*, 1.5.2). It depends on the
substrate the rubber touches, the angle of the light in it and the rubber's index: rubber
on ice at 60 deg returns 2.2 % of the light (darkness 0.978), on glass or acrylic under
0.1 %. The contact analysis uses it as full contact's darkness where no contact in the
video is resolved (:mod:`tir_contact.measure`) and ``meta.json`` names the optics
(``optics.substrate``, ``optics.incidence_deg``; docs/formats.md); stray light and the
camera's black level can only lower it, which the error bar's range holds.

Refractive indices: ice 1.31 and acrylic glass 1.491 (the thesis, Table 4.5), glass 1.52
(crown glass at 550 nm); rubber 1.5 (filled natural or SBR rubber; 1.45-1.6 for other
compounds, which moves the darkness on ice by about 1 %).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

__all__ = [
    "RUBBER_INDEX",
    "SUBSTRATE_INDEX",
    "contact_darkness",
    "full_contact_from_meta",
]

#: Refractive index of the surfaces a TIR rig images contact on (the thesis's Table 4.5 for
#: ice and acrylic glass; crown glass).
SUBSTRATE_INDEX: dict[str, float] = {"ice": 1.31, "acrylic": 1.491, "glass": 1.52}
#: Refractive index of tread rubber assumed when ``optics.rubber_index`` is not given.
RUBBER_INDEX = 1.5


def contact_darkness(substrate_index: float, incidence_deg: float,
                     rubber_index: float = RUBBER_INDEX) -> float:
    """Darkness ``1 - R`` of full contact: unpolarised Fresnel reflectance of light at
    `incidence_deg` in a substrate of `substrate_index` on rubber of `rubber_index`.

    Parameters
    ----------
    substrate_index, rubber_index : float
        Real refractive indices (the rubber's absorption is neglected: carbon black makes
        tread rubber opaque over millimetres but leaves its reflectance near that of a
        dielectric).
    incidence_deg : float
        Angle of the light in the substrate against the surface normal, deg, in [0, 90).

    Returns
    -------
    float
        In [0, 1]; 0 where the light is totally reflected at the rubber too.

    Examples
    --------
    >>> round(contact_darkness(1.31, 60.0), 4)        # rubber on ice
    0.9779
    >>> round(contact_darkness(1.5, 0.0), 6)           # index-matched: nothing reflected
    1.0
    """
    if not (0.0 <= incidence_deg < 90.0):
        raise ValueError(f"incidence_deg must be in [0, 90), got {incidence_deg!r}")
    if substrate_index <= 0 or rubber_index <= 0:
        raise ValueError(f"refractive indices must be > 0, got substrate {substrate_index!r}"
                         f" and rubber {rubber_index!r}")
    n1, n2 = float(substrate_index), float(rubber_index)
    sin_i = math.sin(math.radians(incidence_deg))
    sin_t = n1 * sin_i / n2
    if sin_t >= 1.0:
        return 0.0
    cos_i, cos_t = math.cos(math.radians(incidence_deg)), math.sqrt(1.0 - sin_t ** 2)
    r_s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)
    r_p = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t)
    return 1.0 - 0.5 * (r_s ** 2 + r_p ** 2)


def full_contact_from_meta(meta: Mapping[str, Any]) -> tuple[float, str] | None:
    """Full contact's darkness from ``meta["optics"]``, and its source in words.

    Parameters
    ----------
    meta : mapping
        The footage's metadata (:func:`tir_contact.meta.load_meta`); its ``optics`` entry:
        ``substrate`` (ice, acrylic or glass), ``incidence_deg`` and ``rubber_index``
        (default :data:`RUBBER_INDEX`).

    Returns
    -------
    (float, str) or None
        None where the metadata has no ``optics`` entry.

    Raises
    ------
    ValueError
        Naming the key: one of ``substrate`` and ``incidence_deg`` without the other, an
        unknown substrate, or an angle at which the rig shows no contact (the free surface
        does not reflect totally in air, or the rubber reflects totally too).

    Examples
    --------
    >>> c, how = full_contact_from_meta({"optics": {"substrate": "glass",
    ...                                             "incidence_deg": 60}})
    >>> round(c, 4), how
    (0.9995, 'rubber (n 1.5) on glass (n 1.52) at 60 deg, Fresnel')
    >>> full_contact_from_meta({}) is None
    True
    """
    optics = meta.get("optics")
    if not isinstance(optics, Mapping):
        return None
    substrate, angle = optics.get("substrate"), optics.get("incidence_deg")
    if substrate is None and angle is None:
        return None
    if substrate is None or angle is None:
        given, missing = (("substrate", "incidence_deg") if angle is None
                          else ("incidence_deg", "substrate"))
        raise ValueError(f"'optics.{given}' is given without 'optics.{missing}': full "
                         "contact's darkness needs both")
    name = str(substrate).strip().lower()
    if name not in SUBSTRATE_INDEX:
        raise ValueError(f"'optics.substrate' must be one of {', '.join(SUBSTRATE_INDEX)}, "
                         f"got {substrate!r}")
    n1 = SUBSTRATE_INDEX[name]
    n2 = float(optics.get("rubber_index") or RUBBER_INDEX)
    theta = float(angle)
    lowest, highest = (math.degrees(math.asin(1.0 / n1)),
                       math.degrees(math.asin(min(n2 / n1, 1.0))))
    if not lowest < theta < highest:
        raise ValueError(
            f"'optics.incidence_deg' must lie between {lowest:.1f} deg (below it the free "
            f"surface of {name} does not reflect totally) and {highest:.1f} deg (beyond it "
            f"rubber of index {n2:g} reflects totally too), got {theta:g}")
    c = contact_darkness(n1, theta, n2)
    return c, f"rubber (n {n2:g}) on {name} (n {n1:g}) at {theta:g} deg, Fresnel"
