"""Worker processes of a local batch: started cheaply, single-threaded, and never orphaned.

A worker that outlives its parent (the parent killed with ``kill -9``) would finish its
video and then wait forever for work. Each worker therefore watches the process that
started the batch and exits as soon as it is gone.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import sys
import threading
from multiprocessing.context import BaseContext

import cv2

logger = logging.getLogger(__name__)

__all__ = ["context", "init_worker", "parent_alive"]

#: Seconds between two looks at the parent.
WATCH_INTERVAL_S = 0.5

#: Modules the fork server imports once, so that each worker starts without importing them.
_PRELOAD = ["tir_contact.analyze", "tir_contact._outdir"]


def context() -> BaseContext:
    """The start method of the batch's workers.

    On Linux, while the calling process runs no other thread, ``fork``: the workers start
    at once with everything the parent imported (importing the analysis takes about a
    second, as long as a short video's analysis). Forking a process that runs threads can
    deadlock the child, so otherwise, and on other POSIX systems, ``forkserver`` (workers
    forked from a clean server that imports the analysis once); ``spawn`` elsewhere.
    """
    methods = multiprocessing.get_all_start_methods()
    if sys.platform.startswith("linux") and threading.active_count() == 1 and "fork" in methods:
        return multiprocessing.get_context("fork")
    if sys.platform != "win32" and "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(_PRELOAD)
        return ctx
    return multiprocessing.get_context("spawn")


def parent_alive(pid: int) -> bool:
    """True while process `pid` exists (POSIX signal 0; always True elsewhere)."""
    if os.name != "posix":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def _watch(pid: int) -> None:
    event = threading.Event()
    while not event.wait(WATCH_INTERVAL_S):
        if not parent_alive(pid):
            os._exit(1)  # no clean-up to run: the parent that would read results is gone


def init_worker(parent_pid: int) -> None:
    """Initialise a worker: one OpenCV thread, and exit when `parent_pid` is gone.

    Parameters
    ----------
    parent_pid : int
        Process id of the batch that started the worker.
    """
    cv2.setNumThreads(1)  # the batch already runs one process per core
    threading.Thread(target=_watch, args=(parent_pid,), name="parent-watch",
                     daemon=True).start()
