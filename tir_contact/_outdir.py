"""Atomic output: files and whole result folders appear complete or not at all."""

from __future__ import annotations

import json
import os
import shutil
import uuid
from pathlib import Path
from typing import Any

from friction_model._atomic import atomic_write

__all__ = ["atomic_write", "replace_folder", "staging_folder", "write_json"]


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return None if not np.isfinite(obj) else float(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def _finite(obj: Any) -> Any:
    """Replace NaN/inf floats by None (JSON has no NaN)."""
    if isinstance(obj, float):
        return obj if obj == obj and abs(obj) != float("inf") else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    return obj


def write_json(path: Path, data: Any) -> Path:
    """Write `data` as UTF-8 JSON (sorted keys, NaN as null), atomically."""
    text = json.dumps(_finite(data), indent=2, sort_keys=True, default=_json_default)
    return atomic_write(Path(path), lambda tmp: tmp.write_text(text + "\n", encoding="utf-8"))


def staging_folder(final: Path) -> Path:
    """A new empty folder beside `final` to build results in (hidden name)."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    staging = final.parent / f".{final.name}.{uuid.uuid4().hex[:8]}.partial"
    staging.mkdir()
    return staging


def replace_folder(staging: Path, final: Path) -> Path:
    """Move a finished `staging` folder to `final`, replacing an older result.

    The old folder is first renamed aside, so at every moment `final` is either the old
    complete result or the new one; the aside copy is deleted last.
    """
    final = Path(final)
    aside = None
    if final.exists():
        aside = final.parent / f".{final.name}.{uuid.uuid4().hex[:8]}.old"
        os.replace(final, aside)
    os.replace(staging, final)
    if aside is not None:
        shutil.rmtree(aside, ignore_errors=True)
    return final
