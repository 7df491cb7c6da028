"""The optional finite-element library (scikit-fem), imported only when a model is built."""

from __future__ import annotations

from types import ModuleType

__all__ = ["require_skfem"]

#: The one-line message when scikit-fem is missing.
MISSING = (
    "the continuum element model needs scikit-fem: pip install 'tir-contact[fem]' "
    "(or pip install scikit-fem)"
)


def require_skfem() -> ModuleType:
    """Import and return :mod:`skfem`, or raise ImportError with the install line.

    Returns
    -------
    module
        :mod:`skfem`.

    Raises
    ------
    ImportError
        If scikit-fem is not installed (one line naming the extra to install).
    """
    try:
        import skfem
    except ImportError as exc:
        raise ImportError(MISSING) from exc
    return skfem
