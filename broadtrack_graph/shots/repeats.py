"""Repeated frames: a frame whose image is the previous frame's again. No I/O.

Video converted from one frame rate to another repeats frames: 25 fps content in a 50 fps stream
shows every image twice, 24 or 25 fps content in a 30 fps stream repeats one frame in four or five.
The camera did not stop for a frame and then move twice as far: the scene did not change at all
(players included). A tracker that takes the repeat for a frame of its own sees motion 0, then 2v,
and its smoothness prior, which expects a steady motion, drags the next frame behind the image.
A repeated frame is therefore given the estimate of the frame it repeats, and the solver only sees
the frames of the content.

The test: on grey images reduced to ``work_width_px``, the share of pixels whose grey level changed
by more than ``change_grey_levels`` is under ``max_changed_share``. A re-encoded repeat changes by
compression noise only (a few grey levels); any real frame moves some edges (players walk, the
camera turns) by far more: a pan of one pixel changes every edge in the image (on the real clips of
``bench real --video-dir``: repeats change 0-0.4 % of the image, other frames
1.0 % and up). A frame of a still camera where little moves (a player or two) can pass too: its
camera, which moved well under a pixel, is the previous frame's either way. A slow pan over a narrow view of bare
grass changes as little: a frame that passes is also registered on the one it would repeat (phase correlation) and
repeats it only when shifted under ``max_shift_px`` (on the real clips of ``bench real --video-dir``, repeats are
shifted 0.03 px at most; the 478p clip's six frames that passed the first test, 0.5 px: a pan).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np


@dataclass(frozen=True)
class RepeatConfig:
    """Settings of :func:`repeats`."""

    work_width_px: int = 640  # the images are compared at this width (area averaging) ...
    change_grey_levels: int = 12  # ... a pixel changed when its grey level moved by more than this ...
    max_changed_share: float = 0.005  # ... and the frame repeats the previous one when under this share changed
    #                                   (0: no frame repeats) ...
    max_shift_px: float = 0.2  # ... and the whole image moved under this far (pixels at work_width_px)


AREA_STEP_WIDTH_PX = 960
"""Frames at least twice as wide are first area-averaged to this width in colour (the weight-free detector's working
image, which the decoding thread makes once a frame), then made grey and reduced."""


def reduced_grey(image_bgr: np.ndarray, width_px: int, reduced_bgr: np.ndarray | None = None) -> np.ndarray:
    """(h, min(width_px, W)) uint8: the frame made grey, then reduced to that width by area averaging (grey first:
    the reduction then moves one channel, not three). A frame at least twice :data:`AREA_STEP_WIDTH_PX` wide is
    first area-averaged to that width, whichever way the frame comes (that image exists already where the frames
    are decoded: reducing it is far cheaper than the whole frame's grey and reduction, for a grey level or less).
    The repeat test's image and the optical flow's working image (:func:`broadtrack_graph.detect.flow.prepare`) are
    this.

    reduced_bgr: that area-averaged image when already made (the detector's working image), or None.
    """
    H, W = image_bgr.shape[:2]
    if W >= 2 * AREA_STEP_WIDTH_PX and width_px <= AREA_STEP_WIDTH_PX:
        if reduced_bgr is None or reduced_bgr.shape[1] != AREA_STEP_WIDTH_PX:
            reduced_bgr = cv2.resize(image_bgr, (AREA_STEP_WIDTH_PX, max(1, int(round(H * AREA_STEP_WIDTH_PX / W)))),
                                     interpolation=cv2.INTER_AREA)
        image_bgr = reduced_bgr
    h, w = image_bgr.shape[:2]
    width = min(width_px, w)
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    return grey if width == w else cv2.resize(grey, (width, max(1, int(round(h * width / w)))),
                                              interpolation=cv2.INTER_AREA)


def repeat_grey(image_bgr: np.ndarray, config: RepeatConfig = RepeatConfig(),
                reduced_bgr: np.ndarray | None = None) -> np.ndarray:
    """(h, work_width_px) uint8 grey image of an (H, W, 3) uint8 BGR frame, for :func:`repeats` (``reduced_bgr``:
    as for :func:`reduced_grey`)."""
    return reduced_grey(image_bgr, config.work_width_px, reduced_bgr)


def repeats(previous_grey: np.ndarray | None, grey: np.ndarray, config: RepeatConfig = RepeatConfig()) -> bool:
    """Whether the frame of ``grey`` repeats the frame of ``previous_grey`` (both from :func:`repeat_grey`; None: no
    previous frame)."""
    if previous_grey is None or previous_grey.shape != grey.shape:
        return False
    changed = cv2.absdiff(previous_grey, grey) > config.change_grey_levels
    if float(np.count_nonzero(changed)) >= config.max_changed_share * changed.size:
        return False
    (dx, dy), _ = cv2.phaseCorrelate(previous_grey.astype(np.float32), grey.astype(np.float32))
    return bool(np.hypot(dx, dy) < config.max_shift_px)
