"""One Ctrl-C per run (``tir_contact._interrupt.one_interrupt``): the first stops the work,
a second one cannot cut the clean-up short, also between the batch's block and the
command line's. Truth: the signals this process sends itself."""

from __future__ import annotations

import os
import signal
import time

import pytest

from tir_contact._interrupt import one_interrupt


def _ctrl_c() -> None:
    os.kill(os.getpid(), signal.SIGINT)
    time.sleep(0.05)  # the handler runs at the next bytecode after delivery


@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to itself (POSIX)")
def test_a_second_ctrl_c_between_the_nested_blocks_is_the_same_interrupt():
    # before, the batch's block put Python's own handler back on its way out: a second
    # Ctrl-C before the command line's except (the slow Ctrl-C test, 3 runs in 9) raised
    # again there, and the process died of SIGINT (exit -2 for 130)
    previous = signal.getsignal(signal.SIGINT)
    reached = False
    try:
        with pytest.raises(KeyboardInterrupt):
            with one_interrupt(keep_ignoring=True):  # the command line's
                try:
                    with one_interrupt():  # the batch's
                        _ctrl_c()
                finally:
                    _ctrl_c()  # between the two exits: ignored
                    reached = True
        assert reached
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # until the process ends
        _ctrl_c()  # ignored
        # a library call (no keep_ignoring) puts the previous handler back
        signal.signal(signal.SIGINT, previous)
        with pytest.raises(KeyboardInterrupt), one_interrupt():
            _ctrl_c()
        assert signal.getsignal(signal.SIGINT) is previous
    finally:
        signal.signal(signal.SIGINT, previous)
