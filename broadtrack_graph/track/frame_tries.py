"""The single-frame tries of a re-initialisation: the known cameras' refined guesses, the court model and the learned
field model, each on its own :class:`~broadtrack_graph.track.search_budget.TrySchedule` (a frame none places makes
them wait 1, 2, 4, ... frames; a frame on which the court model forms no hypothesis is no try, unless the shot step
reads it as another view). Each returns its camera, refined or twinned as the run's cameras decide, with the
tracker's confidence; :func:`court_accept_at` is the bar the court model's camera is taken at by itself. The decision
that takes or passes them is :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy`'s. No I/O.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import image_motion_px
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry, Guess
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.reinit_decision import Candidate, CourtCandidate
from broadtrack_graph.track.search_budget import TrySchedule

ModelCamera = Callable[[np.ndarray], ReinitResult]
"""``image_bgr -> ReinitResult``: a camera from the learned field model alone."""
CourtCamera = Callable[..., ReinitResult]
"""``(detections, frame_size, curves) -> ReinitResult``: a camera from the marking map alone, wherever it stands
(:func:`broadtrack_graph.reinit.court.court_reinit`), with its twin."""


class FrameTries:
    """The court model's and the field model's tries (module docstring).

    Args:
        config: the run's thresholds (``confidence_threshold``).
        registry: the run's cameras by id (the twin of a court camera is taken where a known camera stands).
        refine: refines a camera on the frame's marking map (the guesses, the field model's cameras).
        model, court: the two single-frame calibrators, each None when not used.
        counts: the policy's counters (``model_tried``, ``court_tried``), updated here.
    """

    def __init__(self, config: TrackingConfig, registry: CameraRegistry, refine, model: ModelCamera | None,
                 court: CourtCamera | None, counts: dict) -> None:
        self.config, self.registry, self.refine = config, registry, refine
        self.model, self.court, self.counts = model, court, counts
        self.model_schedule, self.court_schedule = TrySchedule(), TrySchedule()
        self.guess_schedule = TrySchedule()  # every known camera's guesses at a shot's start
        self._court_cameras: list[tuple[int, object]] = []  # (frame, camera): the stretch's court cameras
        self._first_court_frame: int | None = None  # the stretch's first frame with a court camera confident by the margin
        self.court_ran_on: int | None = None  # the last frame the court model ran on (its schedule allowing)

    def new_stretch(self) -> None:
        """A cut or a view change: the shot's first frames are tried one by one."""
        self.model_schedule.new_stretch()
        self.court_schedule.new_stretch()
        self.guess_schedule.new_stretch()
        self._court_cameras = []
        self._first_court_frame = None

    def confident(self) -> None:
        """A confident frame: a later loss is tried after 1, 2, 4, ... frames."""
        self.model_schedule.confident()
        self.court_schedule.confident()
        self.guess_schedule.confident()

    def refined_guess(self, frame_index: int, camera_id: str | None, detections, curves, score,
                      held: Camera | None = None) -> Candidate | None:
        """The best refined guess, continuing its camera id's chain (None when there is none): the last confident
        camera of ``camera_id`` (the chain's) on every frame, and ``held`` (the chain's camera the solver holds) when
        given; or, with no camera id (a shot's camera not known), every known camera's on the guess schedule's
        frames."""
        best: Candidate | None = None
        every_camera = camera_id is None
        if not self.config.cheap_reinit or (every_camera and not self.guess_schedule.allows(frame_index)):
            return best
        guesses = self.registry.guesses(frame_index, camera_id, self.config.max_guess_age_frames)
        if held is not None:
            guesses = list(guesses) + [Guess(camera_id, "the held camera", held)]
        for guess in guesses:
            guess_id = guess.camera_id
            refined = self.refine([(guess.label, guess.camera)], detections, curves=curves)
            if refined.camera is None:
                continue
            if every_camera and guess_id in self.registry.positions and not self.registry.stands_at(
                    guess_id, refined.camera.position_m, refined.camera.R_cw[2]):
                continue  # at a shot's start, a known camera's guess that moved elsewhere: another camera's view
            # The refiner scores with the tracker's confidence on the marking map; anything else is judged here.
            confidence = refined.score.jaccard if refined.score is not None else score(refined.camera)
            if confidence is not None and (best is None or confidence > best.confidence):
                best = Candidate(refined, guess_id, float(confidence), True, "refined " + refined.reason)
        if every_camera and guesses:
            confident = best is not None and best.confidence >= self.config.confidence_threshold
            self.guess_schedule.tried(frame_index, confident)
        return best

    def model_camera(self, frame_index: int, image, detections, curves, score) -> Candidate | None:
        """The field model's camera for the frame, refined on the marking map, with its confidence; None when there
        is no model or image, the model is backing off, or it found nothing. Its camera id is given only if it is
        taken (by where it stands)."""
        if self.model is None or image is None or not self.model_schedule.allows(frame_index):
            return None
        self.counts["model_tried"] += 1
        result = self.model(image)
        found = None
        if result.camera is not None:
            refined = self.refine([(result.hypothesis, result.camera)], detections, curves)
            camera = refined.camera if refined.camera is not None else result.camera
            confidence = score(camera)
            if confidence is None:  # no marking map and no lines: the model's own keypoints
                confidence = result.score.inlier_share if result.score is not None else 0.0
            found = Candidate(ReinitResult(camera, result.score, result.hypothesis), None, float(confidence), False,
                              result.hypothesis)
        confident = found is not None and found.confidence >= self.config.confidence_threshold
        self.model_schedule.tried(frame_index, confident)
        return found

    def court_may_run(self, frame_index: int) -> bool:
        """Whether the court model's schedule lets it run on this frame (a court model given)."""
        return self.court is not None and self.court_schedule.allows(frame_index)

    def court_camera(self, observations, detections, curves, score, every_run_counts: bool = False
                     ) -> CourtCandidate | None:
        """The court model's camera for the frame (or its twin, when a known camera stands where the twin does), its
        confidence, and whether it agrees with the court model's camera of a frame shortly before in the stretch
        (both confident by the margin and standing in one place: ``court_agreement_frames``); None without a court
        model or a marking map, while it backs off, or when it found nothing. ``every_run_counts``: a frame that
        formed no hypothesis counts as a try too."""
        i = observations.frame_index
        if self.court is None or getattr(detections, "marking_mask", None) is None or not self.court_schedule.allows(i):
            return None
        self.counts["court_tried"] += 1
        self.court_ran_on = i
        result, camera, twin, confidence = self._court(observations, detections, curves, score)
        if camera is None:
            if result.tried or every_run_counts:  # a frame that formed no hypothesis cost the map's structures only
                self.court_schedule.tried(i, False)
            return None
        self.court_schedule.tried(i, confidence >= self.config.confidence_threshold)
        agrees = False
        if confidence >= self.config.confidence_threshold + self.config.reinit_switch_margin:
            window = self.config.court_agreement_frames
            self._court_cameras = [(k, c) for k, c in self._court_cameras if 0 < i - k <= window]
            agrees = any(self.registry.same_place(c.position_m, camera.position_m, camera.R_cw[2])
                         and image_motion_px(c, camera, reference_width_px=1.0) >= self.config.court_agreement_view_change
                         for _, c in self._court_cameras)
            self._court_cameras.append((i, camera))
            if self._first_court_frame is None:
                self._first_court_frame = i
        return CourtCandidate(replace(result, camera=camera, twin=twin), None, confidence, False, result.hypothesis,
                              agrees=agrees)

    def court_camera_again(self, observations, detections, curves, score) -> CourtCandidate | None:
        """The court model's camera for the frame on other markings of it (its faint look), as :meth:`court_camera`
        gives it but outside the court model's schedule and the stretch's agreement: a second look at one frame."""
        if self.court is None or getattr(detections, "marking_mask", None) is None:
            return None
        result, camera, twin, confidence = self._court(observations, detections, curves, score)
        if camera is None:
            return None
        return CourtCandidate(replace(result, camera=camera, twin=twin), None, confidence, False, result.hypothesis)

    def _court(self, observations, detections, curves, score):
        """(the court model's result, its camera and twin, the tracker's confidence of the camera; camera None when
        it found none)."""
        result = self.court(detections, (observations.width_px, observations.height_px), curves)
        if result.camera is None:
            return result, None, None, 0.0
        camera, twin = result.camera, result.twin
        if twin is not None and self.registry.nearest(camera.position_m, camera.R_cw[2]) is None \
                and self.registry.nearest(twin.position_m, twin.R_cw[2]) is not None:
            camera, twin = twin, camera  # a known camera's tripod decides the twin
        return result, camera, twin, float(score(camera) or 0.0)

    def court_may_agree(self, frame_index: int) -> bool:
        """Whether a court camera confident by the margin, on this frame or one before in the stretch, can still be
        confirmed by the next frames' (within ``court_agreement_frames`` of the stretch's first such frame): a
        provisional camera's search, and a candidate, wait for them."""
        first = self._first_court_frame
        return first is not None and 0 <= frame_index - first < self.config.court_agreement_frames


def court_accept_at(config: TrackingConfig, result: ReinitResult, new_camera: bool = True) -> float:
    """The confidence the court model's camera ``result`` is taken at by itself: ``court_grid_accept_confidence`` when
    the markings it explains hold two straight lines of each direction (``result.explained.line_grid``), else
    ``court_accept_confidence``; never under the confidence its chain is trusted from (the threshold, and the margin
    over it for a new camera)."""
    grid = result.explained is not None and result.explained.line_grid
    bar = config.court_grid_accept_confidence if grid else config.court_accept_confidence
    return max(bar, config.confidence_threshold + (config.reinit_switch_margin if new_camera else 0.0))
