"""Atomic output: files and whole result folders appear complete or not at all."""

from __future__ import annotations

import os
import shutil
import uuid
from pathlib import Path

from friction_model._atomic import atomic_write, write_json

__all__ = ["atomic_write", "replace_folder", "staging_folder", "write_json"]


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
