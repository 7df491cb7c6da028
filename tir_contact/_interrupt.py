"""One Ctrl-C (SIGINT) per run: the first stops the work, further ones cannot cut short
the clean-up after it. Standard library only: the command line imports it before any
command (``tir-contact --help`` stays fast)."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["one_interrupt"]


class _OneInterrupt:
    """The SIGINT handler of :func:`one_interrupt`: raises once, ignores the rest."""

    def __init__(self) -> None:
        self.fired = False

    def __call__(self, signum: int, frame: object) -> None:
        if not self.fired:
            self.fired = True
            raise KeyboardInterrupt


@contextmanager
def one_interrupt(*, keep_ignoring: bool = False) -> Iterator[None]:
    """Inside the block the first Ctrl-C (SIGINT) raises :class:`KeyboardInterrupt` and any
    further one is ignored: an impatient second Ctrl-C must not cut short the clean-up after
    the first (ending the workers, writing the batch report). Only in the main thread
    (elsewhere Python delivers no signal, and it is a no-op).

    On the way out the previous handler is put back; when that is an enclosing block's and
    this one fired, the enclosing one counts as fired too (a second Ctrl-C between the two
    exits is still the same interrupt). `keep_ignoring`: once fired, SIGINT stays ignored
    after the block (a command line's process, which is on its way out: no window between
    the block's end and the exit in which a second Ctrl-C could kill it).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    handler = _OneInterrupt()
    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield
    finally:
        if handler.fired and isinstance(previous, _OneInterrupt):
            previous.fired = True
        signal.signal(signal.SIGINT, signal.SIG_IGN if handler.fired and keep_ignoring
                      else previous)
