"""Shots as the frames go by: boundaries (:mod:`cuts`) and view kinds (:mod:`views`), per frame and per shot.

A frame's view is decided from the frame and from its shot so far: once a shot has
``vote_frames`` frames, the majority of them decides for the rest of the shot (a
close-up whose player steps aside for a frame stays a close-up), before that each
frame's own classification counts. When ``view_change_frames`` pitch-view frames in a row
follow in a shot whose majority is a no-pitch view, a new shot starts at the first of them (a cut or a dissolve the cut step missed:
a close-up melting into the main camera's centre-circle view must not stay a close-up).

The camera of a pitch shot is not known here: the tracker finds it (its camera id names
the tripod it stands on, :mod:`broadtrack_graph.track.camera_ids`) and :func:`~broadtrack_graph.types.shot.place_shot`
writes it into the shot: kind ``main`` (the main camera), ``other-camera`` (another pitch
camera: behind a goal, near a corner, ...) or ``pitch`` (a pitch view no camera was
placed for); ``close-up`` and ``crowd`` shots have no camera, unless the tracker's court model places one on their
markings (the view kind is read from colours: a low camera's goal frame and net can read as a close-up).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.shots.cuts import CutConfig, CutDetector
from broadtrack_graph.shots.views import VIEW_MAIN, ViewConfig, classify_view
from broadtrack_graph.types.shot import Shot


@dataclass(frozen=True)
class ShotConfig:
    """Settings of :class:`ShotSegmenter`."""

    cuts: CutConfig = CutConfig()  # boundary detection
    views: ViewConfig = ViewConfig()  # view classification
    vote_frames: int = 5  # frames of a shot after which its majority view decides
    view_change_frames: int = 8  # pitch-view frames in a row in a no-pitch shot start a new (pitch) shot


@dataclass(frozen=True)
class FrameShot:
    """What the shot step says about one frame.

    shot_index: 0-based index of the frame's shot.
    cut: True when the frame starts a shot (the first frame of the input included).
    kind: the frame's view ("main": a pitch view; or a view with no pitch: close-up, crowd).
    reason: one line (the view's figures).
    """

    shot_index: int
    cut: bool
    kind: str
    reason: str

    @property
    def is_other_view(self) -> bool:
        """A view with no pitch camera to fit (close-up, crowd)."""
        return self.kind != VIEW_MAIN


class ShotSegmenter:
    """Feed frames in order with :meth:`update`; :attr:`shots` lists the shots so far."""

    def __init__(self, config: ShotConfig = ShotConfig()) -> None:
        self.config = config
        self.cuts = CutDetector(config.cuts)
        self.shots: list[Shot] = []
        self._disagree = 0  # frames in a row whose view differs from the current shot's majority
        self._recent: list[str] = []  # the views of the last frames

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
        cut = bool(boundary.cut)
        if self.shots and not cut:
            shot = self.shots[-1]
            majority = max(shot.views, key=shot.views.get)
            # Only a pitch view ends a no-pitch shot this way: a zoomed main-camera view taken for a close-up
            # must not break a tracked shot (the tracker's confidence judges those frames).
            self._disagree = self._disagree + 1 if (view.kind == VIEW_MAIN and majority != VIEW_MAIN) else 0
            if self._disagree >= self.config.view_change_frames and sum(shot.views.values()) >= self.config.vote_frames:
                # The view changed without a cut being seen: the disagreeing frames start a new shot.
                self._split(frame_index)
                cut = True
        if cut or not self.shots:
            self._disagree = 0
            if not self.shots or boundary.cut:
                self.shots.append(Shot(frame_index, frame_index + 1, view.kind, None,
                                       "start" if not self.shots else (boundary.kind or "hard")))
        self._recent = (self._recent + [view.kind])[-self.config.view_change_frames:]
        shot = self.shots[-1]
        shot.end = frame_index + 1
        shot.views[view.kind] = shot.views.get(view.kind, 0) + 1
        total = sum(shot.views.values())
        majority = max(shot.views, key=shot.views.get)
        kind = majority if total >= self.config.vote_frames else view.kind
        shot.kind = majority
        reason = view.reason if kind == view.kind else f"{kind} shot ({shot.views.get(kind, 0)} of {total} frames); {view.reason}"
        return FrameShot(len(self.shots) - 1, cut, kind, reason)

    def _split(self, frame_index: int) -> None:
        """Start a new shot at the first of the disagreeing frames before frame_index (they move to it)."""
        shot = self.shots[-1]
        start = frame_index - (self.config.view_change_frames - 1)
        moved = self._recent[-(self.config.view_change_frames - 1):] if self.config.view_change_frames > 1 else []
        for kind in moved:
            shot.views[kind] -= 1
            if not shot.views[kind]:
                del shot.views[kind]
        shot.end = start
        shot.kind = max(shot.views, key=shot.views.get) if shot.views else shot.kind
        new = Shot(start, start, moved[0] if moved else "main", None, "view")
        for kind in moved:
            new.views[kind] = new.views.get(kind, 0) + 1
        self.shots.append(new)
