"""Collection rules for the whole repository (the package modules' doctests included).

Docstring examples run in the default test run, except those listed in
:data:`SLOW_DOCTESTS`: they run a simulation scan of several seconds and repeat a check that
``tests/`` holds in the default run; they run with ``-m slow`` (CI runs both).
"""

from __future__ import annotations

import pytest

#: Doctests (``module.function``) that run with ``-m slow``, and the default-run test that
#: holds the same check.
SLOW_DOCTESTS = {
    # tests/test_effect_size_transient.py::test_strength_for_transient_size_root
    "synthetic.effect_size.strength_for_transient_effect_size",
    # tests/test_effect_size_transient.py::test_transient_size_cap_is_reported
    "synthetic.effect_size.transient_size_cap",
}


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the doctests of :data:`SLOW_DOCTESTS` slow (before ``-m`` deselects)."""
    for item in items:
        # a doctest item carries its example as ``dtest`` (every pytest version we allow)
        if getattr(item, "dtest", None) is not None and item.name in SLOW_DOCTESTS:
            item.add_marker(pytest.mark.slow)
