"""Markers the test modules share: tests that need an optional extra skip without it."""

from __future__ import annotations

import sys

import pytest

from synthetic.roughness import MissingExtraError, require_tamaas

try:
    require_tamaas()
    HAVE_TAMAAS = True
except MissingExtraError:
    HAVE_TAMAAS = False

# the test extra installs tamaas on every Python it has a wheel for (3.11, 3.12)
needs_tamaas = pytest.mark.skipif(
    not HAVE_TAMAAS,
    reason="tamaas (the contact extra) is not installed; it has wheels for Python 3.11 and "
    f"3.12, this is {sys.version_info.major}.{sys.version_info.minor}",
)
