"""Shots as the frames go by: boundaries (:mod:`cuts`) and view kinds (:mod:`views`), per frame and per shot.

A frame's view is decided from the frame and from its shot so far: once a shot has
``vote_frames`` frames, the majority of them decides for the rest of the shot (a
close-up whose player steps aside for a frame stays a close-up), before that each
frame's own classification counts. Camera ids: every shot of the main view gets
:data:`MAIN_CAMERA_ID`; other views have none (they are not tracked).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from broadtrack_graph.shots.cuts import CutConfig, CutDetector
from broadtrack_graph.shots.views import VIEW_MAIN, ViewConfig, classify_view

MAIN_CAMERA_ID = "main"
"""Camera id of the tracked (main, wide) camera's shots."""


@dataclass(frozen=True)
class ShotConfig:
    """Settings of :class:`ShotSegmenter`."""

    cuts: CutConfig = CutConfig()  # boundary detection
    views: ViewConfig = ViewConfig()  # view classification
    vote_frames: int = 5  # frames of a shot after which its majority view decides


@dataclass
class Shot:
    """A run of frames between two boundaries.

    start, end: first frame index and one past the last (0-based, end exclusive).
    kind: the majority view of its frames ("main", "close-up", "crowd").
    camera_id: :data:`MAIN_CAMERA_ID` for main-view shots, None for other views.
    boundary: how it began: "start" (first frame of the input), "hard" or "dissolve".
    views: frames per view kind.
    """

    start: int
    end: int
    kind: str
    camera_id: str | None
    boundary: str = "start"
    views: dict = field(default_factory=dict)


@dataclass(frozen=True)
class FrameShot:
    """What the shot step says about one frame.

    shot_index: 0-based index of the frame's shot.
    cut: True when the frame starts a shot (the first frame of the input included).
    kind: the frame's view ("main" or another view).
    camera_id: the camera to track this frame with, or None (another view: no camera).
    reason: one line (the view's figures).
    """

    shot_index: int
    cut: bool
    kind: str
    camera_id: str | None
    reason: str

    @property
    def is_other_view(self) -> bool:
        return self.camera_id is None


class ShotSegmenter:
    """Feed frames in order with :meth:`update`; :attr:`shots` lists the shots so far."""

    def __init__(self, config: ShotConfig = ShotConfig()) -> None:
        self.config = config
        self.cuts = CutDetector(config.cuts)
        self.shots: list[Shot] = []
        self._next_index = 0

    def update(self, frame_index: int, image_bgr: np.ndarray | None) -> FrameShot | None:
        """The shot information of frame ``frame_index`` ((H, W, 3) uint8 BGR; None: a missing frame).

        A missing frame returns None and extends the current shot.
        """
        if image_bgr is None:
            if self.shots:
                self.shots[-1].end = frame_index + 1
            return None
        boundary = self.cuts.update(image_bgr)
        view = classify_view(image_bgr, self.config.views)
        if boundary.cut or not self.shots:
            self.shots.append(Shot(frame_index, frame_index + 1, view.kind, None,
                                   "start" if not self.shots else (boundary.kind or "hard")))
        shot = self.shots[-1]
        shot.end = frame_index + 1
        shot.views[view.kind] = shot.views.get(view.kind, 0) + 1
        total = sum(shot.views.values())
        majority = max(shot.views, key=shot.views.get)
        kind = majority if total >= self.config.vote_frames else view.kind
        shot.kind = majority
        shot.camera_id = MAIN_CAMERA_ID if majority == VIEW_MAIN else None
        reason = view.reason if kind == view.kind else f"{kind} shot ({shot.views.get(kind, 0)} of {total} frames); {view.reason}"
        return FrameShot(len(self.shots) - 1, bool(boundary.cut), kind,
                         MAIN_CAMERA_ID if kind == VIEW_MAIN else None, reason)
