"""CI installs every extra the package ships, so no shipped path skips there unnoticed.

Truth: the package's own metadata (pyproject.toml's ``all`` extra, followed through the extras
it names). In CI (``.ci/run`` sets ``TIR_CONTACT_CI``) every distribution ``all`` requires must
be installed; the tests of the dask scheduler (tests/test_sweep.py, tests/test_analyze.py) and
of the Parquet outputs skip only where an extra is missing, which CI then refuses. Outside CI
(a developer with ``.[test]`` only) the check is skipped: that is not a shipped-path run.
"""

from __future__ import annotations

import importlib.metadata
import os
import re

import pytest

_EXTRA = re.compile(r"""extra\s*==\s*["']([^"']+)["']""")
_NAME = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)(?:\[([^\]]*)\])?")


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def requirements_of_extra(extra: str, dist: str = "tir-contact") -> dict[str, set[str]]:
    """Distribution name -> the extras of it required by ``dist[extra]``, followed recursively
    through ``dist``'s own extras (``all = ["tir-contact[test,dask,parquet]"]``)."""
    reqs = importlib.metadata.requires(dist) or []
    out: dict[str, set[str]] = {}
    todo, seen = [extra], set()
    while todo:
        ex = todo.pop()
        if ex in seen:
            continue
        seen.add(ex)
        for req in reqs:
            marker = _EXTRA.search(req)
            if marker is None or marker.group(1) != ex:
                continue
            m = _NAME.match(req)
            name, extras = _norm(m.group(1)), {e.strip() for e in (m.group(2) or "").split(",")}
            extras.discard("")
            if name == _norm(dist):
                todo.extend(extras)
            else:
                out.setdefault(name, set()).update(extras)
    return out


def test_all_extra_covers_the_shipped_optional_paths():
    # the optional code paths the package ships: dask.distributed (analyze --scheduler,
    # run_sweep(scheduler="dask")) and pyarrow (the Parquet copies of the tables)
    reqs = requirements_of_extra("all")
    assert {"dask", "pyarrow"} <= set(reqs)
    assert "distributed" in reqs["dask"]
    assert "pytest" in reqs  # the test extra comes along: `.[all]` runs the suite


@pytest.mark.skipif(not os.environ.get("TIR_CONTACT_CI"), reason="only CI must have every extra")
def test_ci_has_every_requirement_of_all_installed():
    missing = []
    for name, extras in requirements_of_extra("all").items():
        try:
            importlib.metadata.distribution(name)
        except importlib.metadata.PackageNotFoundError:
            missing.append(name)
            continue
        # the extras of a requirement (dask[distributed]): their own requirements, one level
        for req in importlib.metadata.requires(name) or []:
            marker = _EXTRA.search(req)
            if marker is None or marker.group(1) not in extras:
                continue
            sub = _norm(_NAME.match(req).group(1))
            try:
                importlib.metadata.distribution(sub)
            except importlib.metadata.PackageNotFoundError:
                missing.append(f"{sub} (for {name}[{marker.group(1)}])")
    assert not missing, f"CI must install .[all]; missing: {missing}"
