"""When a frame is lost: the cameras the tracker already had first, the global search after.

The global search (:func:`broadtrack_graph.reinit.frame.reinitialise`) costs up to a second or
two of CPU per frame on a real broadcast; a lost stretch must not drop a run far below real
time. Most frames that need a new camera are close to one the tracker had: a blurred pan
after a confident frame, the main camera coming back after a close-up or a replay. So each
lost frame first tries the cheap guesses (:func:`broadtrack_graph.reinit.cheap.refine_guesses`,
one local label-and-fit each):

1. the last confident camera of the current camera id (the shot step's ``main``, ...), if it
   is not older than ``max_guess_age_frames``;
2. the same camera moved to the focal point of the tripod in use, when one is known.

A guess refined to at least ``accept_confidence`` is used; otherwise the global search runs
(at the tripod in use, then, if that is not confident either, at the default positions: a
provisional tripod can be wrong) and the better camera (by confidence) is returned. While
the track still holds a camera (a low frame, not a lost one), the global search runs at
most once every ``tracking_gap_frames``: right cameras of low-resolution frames often score
just under the threshold, and a search per such frame found nothing better at a second of
CPU each. Only confident frames, as the tracker judges them (:meth:`CheapFirstReinit.confident`),
become guesses: a camera under the threshold seeding the next searches kept whole
stretches re-initialising. No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult


@dataclass(frozen=True)
class CheapFirstConfig:
    """Settings of :class:`CheapFirstReinit`."""

    accept_confidence: float = 0.5  # a refined guess scoring this is used without the global search
    tracking_gap_frames: int = 12  # while the track holds (a low frame, not a lost one), a global search at most this often
    guess_margin: float = 0.1  # an unconfident search result replaces the refined guess only when this much better
    max_guess_age_frames: int = 750  # the last confident camera is a guess for this many frames (30 s at 25 fps)
    enabled: bool = True  # False: the global search on every lost frame


Refiner = Callable[[list, object, object], ReinitResult]
"""``(guesses [(label, Camera)], detections, curves) -> ReinitResult`` whose ``score.jaccard`` is the confidence."""


def _confidence(result: ReinitResult | None) -> float | None:
    """The confidence a result carries (None when unknown, e.g. a keypoint re-initialisation or a fake)."""
    if result is None or result.camera is None or result.score is None:
        return None
    return float(result.score.jaccard)


class CheapFirstReinit:
    """A global re-initialisation behind cheap guesses (module docstring).

    Called like the global one: ``policy(observations, detections, pitch, positions, curves, sampling)``.

    Args:
        global_search: the global re-initialisation.
        refine: refines the guesses on the frame's marking map.
        config: thresholds.
    """

    def __init__(self, global_search: Callable[..., ReinitResult], refine: Refiner,
                 config: CheapFirstConfig = CheapFirstConfig(), confidence: Callable | None = None) -> None:
        self.global_search = global_search
        self.refine = refine
        self.config = config
        self.confidence = confidence
        self.camera_id: str | None = None
        self._last_confident: dict[str | None, tuple[int, Camera]] = {}  # camera id -> (frame index, camera)
        self.cheap_successes = 0
        self.global_searches = 0
        self.skipped_searches = 0
        self._last_tracking_search: int | None = None  # frame of the last global search on a held track
        self.last_from_guess = False  # the last camera returned is a refined guess (a confident camera's continuation)

    def switch(self, camera_id: str | None) -> None:
        """The shot step says the following frames are from this camera."""
        self.camera_id = camera_id

    def confident(self, frame_index: int, camera: Camera) -> None:
        """A frame whose camera the tracker trusts: the current camera id's guess from now on."""
        self._last_confident[self.camera_id] = (frame_index, camera)

    def guesses(self, frame_index: int, positions) -> list[tuple[str, Camera]]:
        """(label, camera) guesses for this frame (module docstring), most likely first."""
        if not self.config.enabled or self.camera_id not in self._last_confident:
            return []
        seen, camera = self._last_confident[self.camera_id]
        if not 0 <= frame_index - seen <= self.config.max_guess_age_frames:
            return []
        out = [(f"last confident camera (frame {seen})", camera)]
        if positions is not None and len(positions) == 1:
            tripod = np.asarray(positions[0], float)
            if np.linalg.norm(tripod - camera.position_m) > 0.5:
                out.append((f"last confident camera (frame {seen}) at the tripod", camera.replace(position_m=tripod)))
        return out

    def __call__(self, observations, detections, pitch, positions=None, curves=None, sampling=None,
                 tracking: bool = False) -> ReinitResult:
        """A camera for the frame (module docstring).

        Args:
            tracking: the caller still holds a camera for this frame (its confidence is low, the track
                is not lost); the global search then runs at most once every ``tracking_gap_frames``.
        """
        i = observations.frame_index
        self.last_from_guess = False
        guesses = self.guesses(i, positions)
        cheap = self.refine(guesses, detections, curves) if guesses else None
        cheap_confidence = _confidence(cheap)
        if cheap_confidence is not None and cheap_confidence >= self.config.accept_confidence:
            self.cheap_successes += 1
            self.last_from_guess = True
            return cheap
        if tracking and self._last_tracking_search is not None and \
                0 <= i - self._last_tracking_search < self.config.tracking_gap_frames:
            # A low frame of a held track: a search a few frames ago found nothing better to switch to;
            # the tracked camera stays (a second of CPU per low frame would drop the run far below real time).
            self.skipped_searches += 1
            if cheap is not None and cheap.camera is not None:
                self.last_from_guess = True
                return cheap
            return ReinitResult(None, None, "", f"global search skipped (one ran at frame {self._last_tracking_search})")
        if tracking:
            self._last_tracking_search = i
        self.global_searches += 1
        def searched(at):
            found_now = self.global_search(observations, detections, pitch, at, curves, sampling)
            if self.confidence is not None and found_now.camera is not None:
                # Every search scores its own way (a labelled-lines Jaccard, the map's F-score): judged here,
                # against the guess and the threshold, by the tracker's own confidence.
                score = self.confidence(found_now.camera, observations, detections, curves, sampling)
                if score is not None:
                    found_now = replace(found_now, score=LabelledScore(float(score), 0, 0, 0, 0.0, 0.0))
            return found_now

        result = searched(positions)
        found = _confidence(result)
        if positions is not None and found is not None and found < self.config.accept_confidence:
            # Searched at the tripod in use only: that tripod may be the wrong one (a provisional fit of
            # frames that were themselves off). The default positions get a search of their own.
            self.global_searches += 1
            anywhere = searched(None)
            if anywhere.camera is not None and (_confidence(anywhere) or 0.0) > found:
                result, found = anywhere, _confidence(anywhere)
        if cheap_confidence is not None and (result.camera is None or (
                found is not None and found < self.config.accept_confidence
                and cheap_confidence > found - self.config.guess_margin)):
            # The search found no confident camera either: the refined guess (a confident camera's
            # continuation) is kept unless the search's camera is clearly better.
            self.last_from_guess = True
            return cheap
        return result
