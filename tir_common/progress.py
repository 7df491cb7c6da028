"""One progress bar for long work (tqdm), with one meaning of ``progress``.

``progress=None`` (the default everywhere) shows the bar when stderr is a terminal and hides
it in logs, pipes and tests; ``True`` always shows it; ``False`` never does.
"""

from __future__ import annotations

import sys
from typing import Any

from tqdm.auto import tqdm

__all__ = ["progress_bar", "show_progress"]


def show_progress(progress: bool | None) -> bool:
    """Whether to show a bar: ``progress`` itself, or stderr is a terminal when ``None``.

    Examples
    --------
    >>> show_progress(False), show_progress(True)
    (False, True)
    """
    if progress is None:
        return bool(getattr(sys.stderr, "isatty", lambda: False)())
    return bool(progress)


def progress_bar(total: int | None, *, progress: bool | None = None, **options: Any) -> tqdm:
    """A :class:`tqdm.tqdm` bar over ``total`` steps, shown as :func:`show_progress` says.

    Parameters
    ----------
    total : int or None
        Number of steps (None: unknown).
    progress : bool or None
        ``None`` shows the bar only on a terminal.
    **options
        Passed to tqdm (``desc``, ``unit``, ``leave``, ``position``, ``initial``, ...).

    Examples
    --------
    >>> with progress_bar(3, progress=False, desc="frames") as bar:
    ...     _ = bar.update(3)
    >>> bar.disable, bar.total
    (True, 3)
    """
    options.setdefault("dynamic_ncols", True)
    return tqdm(total=total, disable=not show_progress(progress), **options)
