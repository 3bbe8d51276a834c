"""Re-initialisation from labelled keypoints: the two-point method inside RANSAC over pairs, then refinement.

The two-point method (:mod:`broadtrack_graph.reinit.two_point`): with the focal point at the tripod
and roll 0, two keypoints give f, pan and tilt. Each candidate focal point (default: the common
broadcast positions and their mirror images) is tried with every pair at once.

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y, positive pan turns towards +x. No I/O.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import project_state
from broadtrack_graph.reinit.lines import camera_from_homography
from broadtrack_graph.reinit.positions import candidate_positions
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.reinit.two_point import pair_scores, two_point_cameras


@dataclass(frozen=True)
class _Candidate:
    """A keypoint hypothesis: its key (inliers among all keypoints, then their capped error: higher is better), the
    camera and the focal point it stands at (metres)."""

    key: tuple
    camera: Camera
    position_w: tuple


def reinit_from_keypoints(
    uv_px: np.ndarray,
    points_w: np.ndarray,
    width_px: int,
    height_px: int,
    positions_w=None,
    inlier_px: float = 10.0,
    max_pairs: int = 60,
    seed: int = 0,
    refine_top: int = 3,
    loose_per_focal: float = 0.03,
) -> ReinitResult:
    """Camera from labelled keypoints: two-point method in RANSAC over pairs, then refinement.

    For each candidate focal point (default: :func:`candidate_positions`, the common broadcast
    positions and their mirror images; after a tripod fit the tracker passes its T alone),
    pairs of keypoints give cameras (:func:`~broadtrack_graph.reinit.two_point.two_point_cameras`), scored by the keypoints
    of the whole frame within ``inlier_px`` (then by their capped error). The best hypotheses
    of the ``refine_top`` best positions are refined on their inliers (first within
    max(4 ``inlier_px``, ``loose_per_focal`` f) since a focal point metres off moves the keypoints
    in proportion to f, then 2x and 1x ``inlier_px``: f, pan, tilt, roll and the focal point,
    Cauchy-weighted Gauss-Newton, weak priors) and re-scored; the best wins. ``inlier_px`` 10 suits keypoints a few px off
    (a heatmap detector's ~3 px).

    Args:
        uv_px: (N, 2) pixels; points_w: (N, 3) metres. N >= 2.

    Returns:
        ReinitResult (score.inlier_share = share of keypoints within inlier_px; jaccard unused = 0).
    """
    uv_px = np.asarray(uv_px, float).reshape(-1, 2)
    points_w = np.asarray(points_w, float).reshape(-1, 3)
    if len(uv_px) < 2:
        return ReinitResult(None, None, "", "fewer than 2 keypoints")
    positions = candidate_positions() if positions_w is None else [tuple(p) for p in positions_w]
    rng = np.random.default_rng(seed)
    pairs = list(itertools.combinations(range(len(uv_px)), 2))
    if len(pairs) > max_pairs:
        pairs = [pairs[i] for i in rng.choice(len(pairs), max_pairs, replace=False)]
    # Hypotheses: the best pair per candidate focal point, scored by inliers among ALL keypoints.
    pair_index = np.asarray(pairs, int).reshape(-1, 2)
    per_position: list[_Candidate] = []
    for position in positions:
        cameras = two_point_cameras(uv_px[pair_index], points_w[pair_index], position, width_px, height_px)
        count, capped = pair_scores(cameras, position, uv_px, points_w, width_px, height_px, inlier_px)
        if count.max() < 0:
            continue
        # The first pair with the most inliers, then the least capped error (pairs in order, as a loop would).
        k = int(np.argmax(np.where(count == count.max(), capped, -np.inf)))
        camera = Camera(float(cameras[k, 0]), 0.0, float(cameras[k, 1]), float(cameras[k, 2]), 0.0,
                        np.asarray(position, float), width_px, height_px)
        per_position.append(_Candidate((int(count[k]), float(capped[k])), camera, position))
    if not per_position:
        return ReinitResult(None, None, "", "no keypoint pair gave a camera", len(pairs))
    # The most promising hypotheses are refined on their inliers (loose, then tight) and re-scored.
    per_position.sort(key=lambda item: item.key, reverse=True)
    best: _Candidate | None = None
    for candidate in per_position[:refine_top]:
        camera, position = candidate.camera, candidate.position_w
        # A focal point metres off shifts the far keypoints in proportion to f: start loose.
        for threshold in (max(4.0 * inlier_px, loose_per_focal * camera.focal_px), 2.0 * inlier_px, inlier_px):
            _, inliers = _score(camera, uv_px, points_w, threshold)
            if inliers.sum() >= 3:
                camera = _refine_on_keypoints(camera, uv_px[inliers], points_w[inliers], np.asarray(position, float))
        key, _ = _score(camera, uv_px, points_w, inlier_px)
        if best is None or key > best.key:
            best = _Candidate(key, camera, position)
    camera, position = best.camera, best.position_w
    uv, front = camera.project(points_w)
    err = np.where(front, np.linalg.norm(uv - uv_px, axis=1), np.inf)
    share = float(np.mean(err < inlier_px))
    score = LabelledScore(0.0, 0, 0, 0, share, float(np.mean(np.minimum(err, 100.0))))
    return ReinitResult(camera, score, f"two-point at {tuple(round(v) for v in position)}", tried=len(pairs))


def camera_from_keypoints(uv_px: np.ndarray, points_w: np.ndarray, width_px: int, height_px: int,
                          inlier_px: float | None = None, positions_w=None) -> ReinitResult:
    """A full camera (f, pan, tilt, roll, focal point) from labelled keypoints, wherever the camera stands.

    With at least 4 keypoints on the grass: a RANSAC homography (pitch plane -> pixels) within
    ``inlier_px``, decomposed into a camera (:func:`~broadtrack_graph.reinit.lines.camera_from_homography`),
    refined on the homography's inliers, then on the camera's own inliers (every keypoint, the crossbar's too: f, pan, tilt, roll and the
    focal point, Cauchy-weighted Gauss-Newton, the focal point only weakly held), loose then tight.
    With fewer, or when the homography gives no camera, the two-point method at the candidate
    positions (:func:`reinit_from_keypoints`). k1 is 0.

    Args:
        uv_px: (N, 2) pixels; points_w: (N, 3) metres.
        inlier_px: a keypoint within this many pixels is an inlier (default 1 % of the width: a
            heatmap detector's few pixels, at any resolution).
        positions_w: candidate focal points for the two-point fallback (default: the broadcast positions).

    Returns:
        ReinitResult; ``score.inlier_share`` is the share of keypoints within ``inlier_px``,
        ``score.tp`` their number (a homography of 4 points always fits: judge by more).
    """
    uv_px = np.asarray(uv_px, float).reshape(-1, 2)
    points_w = np.asarray(points_w, float).reshape(-1, 3)
    inlier_px = float(inlier_px) if inlier_px is not None else max(4.0, 0.01 * width_px)
    ground = np.flatnonzero(points_w[:, 2] == 0.0)
    camera = None
    if len(ground) >= 4:
        H, mask = cv2.findHomography(points_w[ground, :2], uv_px[ground], cv2.RANSAC, inlier_px)
        if H is not None and np.isfinite(H).all() and mask is not None and mask.sum() >= 4:
            agreeing = ground[mask.ravel() > 0]
            camera = camera_from_homography(H, width_px, height_px, points_w[agreeing])
            if camera is not None:  # the decomposition of a noisy homography can be tens of pixels off
                camera = _refine_on_keypoints(camera, uv_px[agreeing], points_w[agreeing], camera.position_m,
                                              sigma_position_m=50.0)
    if camera is None:
        result = reinit_from_keypoints(uv_px, points_w, width_px, height_px, positions_w=positions_w,
                                       inlier_px=inlier_px)
        if result.camera is None:
            return result
        camera, hypothesis = result.camera, result.hypothesis
    else:
        hypothesis = "keypoint homography"
        start = camera.position_m
        for threshold in (4.0 * inlier_px, 2.0 * inlier_px, inlier_px):
            _, inliers = _score(camera, uv_px, points_w, threshold)
            if inliers.sum() >= 4:
                camera = _refine_on_keypoints(camera, uv_px[inliers], points_w[inliers], start, sigma_position_m=50.0)
    uv, front = camera.project(points_w)
    err = np.where(front, np.linalg.norm(uv - uv_px, axis=1), np.inf)
    inliers = err < inlier_px
    score = LabelledScore(0.0, int(inliers.sum()), 0, 0, float(np.mean(inliers)), float(np.mean(np.minimum(err, 100.0))))
    return ReinitResult(camera, score, hypothesis)


def _score(camera: Camera, uv_px: np.ndarray, points_w: np.ndarray, inlier_px: float):
    """((inlier count, -sum of errors capped at inlier_px), inlier mask (N,)) of a camera on keypoints."""
    uv, front = camera.project(points_w)
    err = np.where(front, np.linalg.norm(uv - uv_px, axis=1), np.inf)
    inliers = err < inlier_px
    return (int(inliers.sum()), -float(np.sum(np.minimum(err, inlier_px)))), inliers


def _refine_on_keypoints(camera: Camera, uv_px, points_w, position_w, iterations: int = 15,
                         cauchy_px: float = 5.0, sigma_position_m: float = 5.0) -> Camera:
    """Gauss-Newton on keypoint reprojection (free: f, pan, tilt, roll, C; k1 held), Cauchy weights, priors."""
    if len(uv_px) < 3:
        return camera
    W, H = camera.width_px, camera.height_px
    state = camera.to_vector()
    free = np.array([0, 2, 3, 4, 5, 6, 7])
    prior_sig = np.array([np.inf, np.inf, np.inf, np.inf, math.radians(1.0), sigma_position_m, sigma_position_m, sigma_position_m])
    for _ in range(iterations):
        uv, J_uv, front = project_state(state, points_w, W, H)
        if not front.all():
            break
        r = (uv - uv_px).ravel()
        J = J_uv.reshape(-1, 8)
        w = 1.0 / (1.0 + (r / cauchy_px) ** 2)
        prior_r = np.zeros(8)
        prior_r[4] = state[4]
        prior_r[5:8] = state[5:8] - position_w
        pw = np.where(np.isfinite(prior_sig), 1.0 / prior_sig**2, 0.0)
        A = (J * w[:, None]).T @ J + np.diag(pw)
        g = (J * w[:, None]).T @ r + pw * prior_r
        A, g = A[np.ix_(free, free)], g[free]
        try:
            delta = np.linalg.solve(A + 1e-6 * np.diag(np.diag(A)), -g)
        except np.linalg.LinAlgError:
            break
        state[free] += delta
        if np.max(np.abs(delta[1:4])) < 1e-8:
            break
    try:
        return Camera.from_vector(state, W, H)
    except ValueError:
        return camera
