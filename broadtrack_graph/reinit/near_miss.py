"""A camera found near the right one but not at it, moved to where the map says it stands. No I/O.

A search that puts its hypotheses at a candidate focal point metres from where the camera
stands can settle on a camera that explains much of the marking map without being right:

* **along its line of sight** (:func:`along_line_of_sight`): a view seen from a few metres nearer
  with a shorter lens (or further with a longer one) looks almost the same around the point the
  camera looks at;
* **off its candidate position** (:func:`walk_wide`): the fit's prior holds the focal point within
  a few metres of the candidate, so a camera standing further away is pulled only part of the way.

The tracker's policy (:mod:`broadtrack_graph.track.reinit_policy`) decides when these are tried
and keeps a moved camera only when it is more confident by its margin.
"""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.mask import fit_points, refine_on_map
from broadtrack_graph.reinit.mask_config import MaskSearchConfig

LINE_OF_SIGHT_SCALES = (0.9, 0.95, 1.05, 1.1, 1.2)
"""Distances (shares of the camera's distance to the ground point it looks at) tried by :func:`along_line_of_sight`."""


def fits_here(function: Callable, calls: Sequence[tuple], curves: TemplateCurves, **keywords) -> list:
    """``function(*args, curves=curves, **keywords)`` for each ``args`` of ``calls``, one after the other (the
    default ``fits`` of :func:`along_line_of_sight`; the tracker's runs them on its search workers too)."""
    return [function(*args, curves=curves, **keywords) for args in calls]


def along_line_of_sight(camera: Camera, marking_points_px: np.ndarray, curves: TemplateCurves,
                        config: MaskSearchConfig = MaskSearchConfig(),
                        scales=LINE_OF_SIGHT_SCALES, fits: Callable = fits_here) -> list[Camera]:
    """The camera moved along its optical axis, f scaled with its distance, each refined on the map.

    A view seen from a few metres nearer with a shorter lens (or further with a longer one) looks
    almost the same around the point the camera looks at: a search can settle on a camera 5-10 %
    too near or too far that explains most of the map (measured on a real 360p main-camera frame:
    3 m too near, f 6 % short, confidence 0.63 against 0.80). The focal point is moved to
    ``s`` times its distance from the ground point on the optical axis (f times ``s``), then refined
    (:func:`refine_on_map`, the position held near the moved one).

    Args:
        camera: the camera found (any focal point above the pitch, looking down at it).
        marking_points_px: (M, 2) centre-line points of the map, frame pixels.
        scales: the distances tried, as shares of the camera's.
        fits: runs the independent label-and-fit runs, :func:`fits_here` or alike (the same cameras, in order).

    Returns:
        The refined cameras, one per scale (none when the optical axis does not meet the ground).
    """
    position = np.asarray(camera.position_m, float)
    axis = np.asarray(camera.R_cw[2], float)  # optical axis in the pitch frame
    if axis[2] <= 1e-6 or position[2] >= 0.0:
        return []
    looked_at = position + (-position[2] / axis[2]) * axis
    points = fit_points(marking_points_px, config)
    calls = []
    for scale in scales:
        moved = looked_at + scale * (position - looked_at)
        calls.append((camera.replace(focal_px=camera.focal_px * scale, position_m=tuple(moved)), points, moved))
    return list(fits(refine_on_map, calls, curves, config=config, schedule=config.schedule))


def best_along_line_of_sight(camera: Camera, score, marking_points_px: np.ndarray, curves: TemplateCurves,
                             fits: Callable = fits_here) -> tuple[float, Camera | None]:
    """(score, camera) of the best of :func:`along_line_of_sight` (its fits run by ``fits``) by ``score`` (camera ->
    float or None).

    (0, None) when there is none."""
    scored = [(score(c) or 0.0, c) for c in along_line_of_sight(camera, marking_points_px, curves, fits=fits)]
    return max(scored, key=lambda item: item[0], default=(0.0, None))


WALK_FROM_CONFIDENCE = 0.3
"""A camera explaining less of the marking map than this is not a near miss: it is not walked."""


def walk_wide(camera: Camera, marking_points_px: np.ndarray, curves: TemplateCurves,
              config: MaskSearchConfig = MaskSearchConfig()) -> Camera | None:
    """The wide label-and-fit repeated, each time from where the last one went (the prior on the focal point
    re-centred there).

    Measured on a real 360p main-camera frame: found 5 m off (4.6 m too near, 1 m low) with f 18 % short
    (confidence 0.43), one wide fit moved it 3.8 m (0.50), and two more took it to the camera the tracker holds
    on that shot (0.77). Stops when a fit moves the focal point less than ``config.walk_still_m``, after at most
    ``config.walk_max_fits`` fits.

    Args:
        camera: the camera found; marking_points_px: (M, 2) centre-line points of the map, frame pixels.

    Returns:
        The camera where the walk stopped, or None when the first fit did not move its focal point (or the
        config has no wide schedule).
    """
    if config.wide_schedule is None:
        return None
    points = fit_points(marking_points_px, config)
    walked = False
    for _ in range(config.walk_max_fits):
        fitted = refine_on_map(camera, points, camera.position_m, curves, config, config.wide_schedule)
        moved_m = float(np.linalg.norm(np.subtract(fitted.position_m, camera.position_m)))
        camera = fitted
        if moved_m < config.walk_still_m:
            break
        walked = True
    return camera if walked else None


def best_walked(cameras: Sequence[tuple[float, Camera]], score: Callable[[Camera], float | None],
                marking_points_px: np.ndarray, curves: TemplateCurves, enough: float,
                ) -> tuple[float, Camera | None, int, int]:
    """Walk (:func:`walk_wide`) the near misses among found cameras, most confident first, until one is ``enough``.

    Args:
        cameras: (confidence, camera) pairs; those under :data:`WALK_FROM_CONFIDENCE` or already ``enough``
            are not walked.
        score: camera -> confidence (None counts as 0).

    Returns:
        (confidence, camera, index into ``cameras`` it was walked from) of the most confident walked camera
        ((0, None, -1) when none moved), and how many cameras were walked.
    """
    best: tuple[float, Camera | None, int] = (0.0, None, -1)
    walks = 0
    for index in sorted(range(len(cameras)), key=lambda k: -cameras[k][0]):
        if not WALK_FROM_CONFIDENCE <= cameras[index][0] < enough:
            continue
        walks += 1
        walked = walk_wide(cameras[index][1], marking_points_px, curves)
        confidence = 0.0 if walked is None else float(score(walked) or 0.0)
        if walked is not None and confidence > best[0]:
            best = (confidence, walked, index)
        if best[0] >= enough:
            break
    return (*best, walks)
