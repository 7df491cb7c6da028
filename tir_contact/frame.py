"""One frame in, its numbers out: the per-frame step of :func:`tir_contact.analyze.analyze_video`.

The step is the video's view's (:attr:`tir_contact.prepare.VideoSetup.view`):
:class:`tir_contact.tir_view.TirFrames` for TIR footage (contact test, darkness in the
contact's box, regions, block, elements and front-edge peaks, the area's error bar, regions
at the lit zone's rim), :class:`tir_contact.side_view.SideFrames` for a side view (darkness
against the background, element chords). :class:`FrameAnalyser` runs it for every frame of
a video; :func:`analyze_frame` is the same for one frame.
"""

from __future__ import annotations

import numpy as np

from tir_contact.options import AnalysisOptions
from tir_contact.prepare import VideoSetup
from tir_contact.view import FrameResult, fully_in_view

__all__ = ["FrameAnalyser", "FrameResult", "analyze_frame", "fully_in_view"]


def analyze_frame(frame: np.ndarray, setup: VideoSetup, options: AnalysisOptions | None = None,
                  *, k: int = 0) -> FrameResult:
    """Analyse one frame of a video whose setup is known.

    Parameters
    ----------
    frame : (M, N) ndarray
        The frame.
    setup : VideoSetup
        What :func:`tir_contact.prepare.prepare_video` found for the video.
    options : AnalysisOptions, optional
        Settings (the defaults when omitted).
    k : int
        The frame's recorded number (its time is ``k / fps``).

    Returns
    -------
    FrameResult
    """
    return FrameAnalyser(setup, options or AnalysisOptions())(k, frame)


class FrameAnalyser:
    """Analyses the frames of one video with fixed settings: ``analyser(k, frame)``.

    Parameters
    ----------
    setup : VideoSetup
    options : AnalysisOptions

    Attributes
    ----------
    step : TirFrames or SideFrames
        The view's per-frame step (:meth:`tir_contact.view.View.analyser`).
    want_regions : bool
        Whether the results hold the contact regions (``regions.csv``).
    """

    def __init__(self, setup: VideoSetup, options: AnalysisOptions) -> None:
        self.setup = setup
        self.options = options
        self.step = setup.view.analyser(setup, options)
        self.want_regions = bool(self.step.want_regions)

    def __call__(self, k: int, frame: np.ndarray) -> FrameResult:
        """Analyse frame `frame`, recorded frame number `k`."""
        return self.step(k, frame)
