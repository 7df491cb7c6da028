"""Worker processes of a local batch: started cheaply, single-threaded, and never orphaned.

A worker that outlives its parent (the parent killed with ``kill -9``) would finish its
video and then wait forever for work. Each worker therefore watches the process that
started the batch and exits as soon as it is gone. Workers ignore Ctrl-C (SIGINT): the
batch's process alone decides, and ends them (:func:`end_workers`) when it is interrupted.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import sys
import threading
from multiprocessing.context import BaseContext

import cv2

logger = logging.getLogger(__name__)

__all__ = ["children", "context", "end_workers", "init_worker",
           "parent_alive"]

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


def children() -> set[multiprocessing.process.BaseProcess]:
    """The worker processes this process has started and that still run."""
    return set(multiprocessing.active_children())


def end_workers(before: set[multiprocessing.process.BaseProcess],
                timeout_s: float = 5.0) -> None:
    """End the worker processes started since `before` (:func:`children`) was taken.

    Each gets SIGTERM (a video half done leaves only a hidden staging folder, which
    :func:`tir_contact._outdir.remove_stale_temporaries` removes once the worker is gone);
    one still alive after `timeout_s` gets SIGKILL.
    """
    mine = [p for p in multiprocessing.active_children() if p not in before]
    for p in mine:
        p.terminate()
    for p in mine:
        p.join(timeout_s)
        if p.is_alive():
            p.kill()
            p.join()


def _watch(pid: int) -> None:
    event = threading.Event()
    while not event.wait(WATCH_INTERVAL_S):
        if not parent_alive(pid):
            os._exit(1)  # no clean-up to run: the parent that would read results is gone


def init_worker(parent_pid: int) -> None:
    """Initialise a worker: one OpenCV thread, Ctrl-C left to the batch's process, and
    exit when `parent_pid` is gone.

    Parameters
    ----------
    parent_pid : int
        Process id of the batch that started the worker.
    """
    cv2.setNumThreads(1)  # the batch already runs one process per core
    # Ctrl-C reaches the whole process group; the batch ends its workers itself (a worker
    # that took it would turn it into a failed video and go on to the next one)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_watch, args=(parent_pid,), name="parent-watch",
                     daemon=True).start()
