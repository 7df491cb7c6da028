"""Tread-block geometry (Fig. 4.4 d) and the reference samples G0-G7 (Table 4.4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tir_common.validate import check_nonnegative, check_positive

__all__ = ["REFERENCE_SAMPLES", "BlockGeometry", "as_geometry", "reference_block"]


@dataclass(frozen=True)
class BlockGeometry:
    """A (siped) tread block: elements of length ``l_i`` separated by sipes.

    Parameters
    ----------
    length_mm : float
        Overall block length L in the sliding direction, mm (thesis samples: 20 mm).
    width_mm : float
        Block width w across the sliding direction, mm (thesis samples: 80 mm).
    n_sipes : int
        Number of sipes; the block has ``n_sipes + 1`` elements.
    sipe_width_mm : float
        Width f of each sipe gap in the sliding direction, mm. The thesis does not state it
        for the reference samples; 0.6 mm is a typical passenger-car sipe.
    height_mm : float
        Element height (sipe depth d), mm. 6 mm as in chapter 5 of the thesis.
    element_lengths_mm : tuple of float, optional
        Lengths l_i of the elements from the leading one; by default the block length minus
        the sipes is split equally.

    Notes
    -----
    Element 0 is the leading element (it meets virgin ice first).
    """

    length_mm: float = 20.0
    width_mm: float = 80.0
    n_sipes: int = 0
    sipe_width_mm: float = 0.6
    height_mm: float = 6.0
    element_lengths_mm: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        check_positive("length_mm", self.length_mm)
        check_positive("width_mm", self.width_mm)
        check_positive("height_mm", self.height_mm)
        check_nonnegative("sipe_width_mm", self.sipe_width_mm)
        if int(self.n_sipes) != self.n_sipes or self.n_sipes < 0:
            raise ValueError(f"n_sipes must be an integer >= 0, got n_sipes={self.n_sipes!r}")
        if self.element_lengths_mm is not None:
            lengths = tuple(float(x) for x in self.element_lengths_mm)
            if len(lengths) != self.n_sipes + 1:
                raise ValueError(
                    "element_lengths_mm must have n_sipes + 1 = "
                    f"{self.n_sipes + 1} entries, got {len(lengths)}"
                )
            for i, x in enumerate(lengths):
                check_positive(f"element_lengths_mm[{i}]", x)
            total = sum(lengths) + self.n_sipes * self.sipe_width_mm
            if abs(total - self.length_mm) > 1e-6 * self.length_mm:
                raise ValueError(
                    "element_lengths_mm plus the sipes must add up to length_mm="
                    f"{self.length_mm}, got {total:.6g} mm"
                )
            object.__setattr__(self, "element_lengths_mm", lengths)
        elif self.length_mm - self.n_sipes * self.sipe_width_mm <= 0:
            raise ValueError(
                f"the sipes (n_sipes={self.n_sipes} x sipe_width_mm={self.sipe_width_mm}) leave "
                f"no rubber in a block of length_mm={self.length_mm}"
            )

    @property
    def n_elements(self) -> int:
        """Number of block elements, ``n_sipes + 1``."""
        return int(self.n_sipes) + 1

    @property
    def element_lengths(self) -> np.ndarray:
        """Element lengths l_i from the leading element, mm."""
        if self.element_lengths_mm is not None:
            return np.asarray(self.element_lengths_mm, dtype=float)
        rubber = self.length_mm - self.n_sipes * self.sipe_width_mm
        return np.full(self.n_elements, rubber / self.n_elements)

    @property
    def element_front_positions_mm(self) -> np.ndarray:
        """Distance of each element's leading edge behind the block's leading edge, mm."""
        lengths = self.element_lengths
        starts = np.concatenate([[0.0], np.cumsum(lengths[:-1] + self.sipe_width_mm)])
        return starts

    @property
    def nominal_area_mm2(self) -> float:
        """Footprint L * w including the sipes, mm^2 (the rig's nominal area)."""
        return self.length_mm * self.width_mm

    @property
    def rubber_area_mm2(self) -> float:
        """Sum of the element faces l_i * w, mm^2."""
        return float(self.element_lengths.sum() * self.width_mm)


REFERENCE_SAMPLES: dict[str, BlockGeometry] = {
    name: BlockGeometry(length_mm=20.0, width_mm=80.0, n_sipes=n)
    for name, n in (("G0", 0), ("G3", 3), ("G5", 5), ("G6", 6), ("G7", 7))
}


def reference_block(name: str) -> BlockGeometry:
    """Return the reference sample ``name`` (G0, G3, G5, G6 or G7; 20 mm x 80 mm).

    Parameters
    ----------
    name : str
        Sample marking as in Table 4.4 / Fig. 4.21.

    Returns
    -------
    BlockGeometry

    Examples
    --------
    >>> reference_block("G3").n_elements
    4
    """
    try:
        return REFERENCE_SAMPLES[name.upper()]
    except KeyError:
        raise ValueError(
            f"unknown reference sample {name!r}; expected one of {sorted(REFERENCE_SAMPLES)}"
        ) from None


def as_geometry(geometry: BlockGeometry | str) -> BlockGeometry:
    """The block `geometry` is, or the reference sample it names (``"G3"``).

    Parameters
    ----------
    geometry : BlockGeometry or str
        A block, or a reference sample's marking (Table 4.4, any case).

    Returns
    -------
    BlockGeometry

    Raises
    ------
    ValueError
        An unknown marking.
    TypeError
        Neither a block nor a marking.

    Examples
    --------
    >>> as_geometry("g3") == reference_block("G3")
    True
    """
    if isinstance(geometry, BlockGeometry):
        return geometry
    if isinstance(geometry, str):
        return reference_block(geometry)
    raise TypeError(
        "geometry must be a BlockGeometry or a reference sample's name "
        f"({', '.join(sorted(REFERENCE_SAMPLES))}), got {type(geometry).__name__}"
    )
