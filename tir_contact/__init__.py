"""tir-contact: TIR contact analysis of tread blocks sliding on ice.

The command-line interface lives in :mod:`tir_contact.cli`; the friction model and the
test-rig evaluation live in the sibling package :mod:`friction_model`.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tir-contact")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
