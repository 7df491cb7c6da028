"""Atomic output: files and whole result folders appear complete or not at all."""

from __future__ import annotations

import logging
import os
import re
import shutil
import uuid
from pathlib import Path

from tir_contact._workers import parent_alive

logger = logging.getLogger(__name__)

__all__ = [
    "remove_stale_temporaries",
    "replace_folder",
    "staging_folder",
    "temporary_name",
]

#: Hidden temporaries this module names: ``.<name>.<pid>-<hex>.partial`` (a result being
#: built), ``.<name>.<pid>-<hex>.old`` (a replaced result being deleted) and
#: ``.<name>.<pid>-<hex><suffix>`` files; the pid is the process that made them. Older
#: versions wrote ``.overlay-XXXXXXXX.avi`` (no pid).
_TEMPORARY = re.compile(
    r"^\..+\.(?:(\d+)-)?[0-9a-f]{8}(?:\.partial|\.old|\.[a-z0-9]+)$"
    r"|^\.overlay-[a-z0-9_]{8}\.avi$"
)


def temporary_name(name: str, suffix: str) -> str:
    """A hidden name for a temporary of this process: ``.<name>.<pid>-<hex><suffix>``."""
    return f".{name}.{os.getpid()}-{uuid.uuid4().hex[:8]}{suffix}"


def staging_folder(final: Path) -> Path:
    """A new empty folder beside `final` to build results in (hidden name)."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    staging = final.parent / temporary_name(final.name, ".partial")
    staging.mkdir()
    return staging


def remove_stale_temporaries(folder: Path) -> list[Path]:
    """Delete the temporaries a killed run left in `folder`.

    A temporary is stale when the process named in it is gone (or it names none: an older
    version made it). Temporaries of a run still going on are kept.

    Returns
    -------
    list of Path
        What was removed.
    """
    removed = []
    try:
        entries = list(Path(folder).iterdir())
    except OSError:
        return removed
    for entry in entries:
        match = _TEMPORARY.match(entry.name)
        if match is None or (match.group(1) and parent_alive(int(match.group(1)))):
            continue
        if entry.is_dir():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink(missing_ok=True)
        removed.append(entry)
    if removed:
        logger.info("%s: removed %d temporaries of an interrupted run", folder, len(removed))
    return removed


def replace_folder(staging: Path, final: Path) -> Path:
    """Move a finished `staging` folder to `final`, replacing an older result.

    The old folder is first renamed aside, so at every moment `final` is either the old
    complete result or the new one; the aside copy is deleted last.
    """
    final = Path(final)
    aside = None
    if final.exists():
        aside = final.parent / temporary_name(final.name, ".old")
        os.replace(final, aside)
    os.replace(staging, final)
    if aside is not None:
        shutil.rmtree(aside, ignore_errors=True)
    return final
