"""Re-initialisation from labelled keypoints: the two-point method inside RANSAC over pairs, then refinement.

The two-point method: with the focal point at the tripod and roll 0, the angle between the
rays of two keypoints gives f, and rotating the two world rays onto the two camera rays
gives pan and tilt. Each candidate focal point (default: the common broadcast positions and
their mirror images) is tried.

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y, positive pan turns towards +x. No I/O.
"""

from __future__ import annotations

import itertools
import math

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera, angles_from_rotation
from broadtrack_graph.geometry.state import project_state
from broadtrack_graph.reinit.lines import camera_from_homography
from broadtrack_graph.reinit.positions import candidate_positions
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult


def focal_from_ray_angle(uv_px: np.ndarray, angle_rad: float, width_px: int, height_px: int) -> float | None:
    """Focal length (pixels) at which the rays of two pixels make a given angle.

    The angle between the rays ``(u - cx, v - cy, f)`` decreases monotonically with f, so it is
    solved by bisection on log f. None when the angle cannot be reached.
    """
    d = np.asarray(uv_px, dtype=float) - [width_px / 2.0, height_px / 2.0]

    def angle(f: float) -> float:
        a = np.array([d[0, 0], d[0, 1], f])
        b = np.array([d[1, 0], d[1, 1], f])
        return math.acos(float(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1)))

    lo, hi = 0.05 * width_px, 50.0 * width_px
    if not (angle(hi) <= angle_rad <= angle(lo)):
        return None
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if angle(mid) > angle_rad:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)


def camera_from_two_points(uv_px, points_w, position_w, width_px: int, height_px: int,
                           steps: int = 4) -> Camera | None:
    """The two-point method: focal point fixed at position_w, roll 0, k1 0.

    Args:
        uv_px: (2, 2) pixels of two pitch points; points_w: (2, 3) their positions (metres).
        position_w: (3,) focal point (the tripod T).
        steps: fixed-point steps on (pan, tilt) once roll is set to 0.

    The rotation that carries the two world rays onto the two camera rays (f from their angle)
    gives pan and tilt; dropping its roll moves the points, so a few Gauss-Newton steps on
    (pan, tilt) alone then bring the two points back (least squares over both). Sign facts
    used by the steps, for a camera looking down at the pitch: +pan moves points towards -u by
    about f sin(tilt) per radian, +tilt moves them towards +v by about f per radian.

    Returns:
        The camera, or None when the pair is degenerate or the angle cannot be matched.
    """
    uv_px = np.asarray(uv_px, dtype=float).reshape(2, 2)
    rays_w = np.asarray(points_w, dtype=float).reshape(2, 3) - np.asarray(position_w, dtype=float)
    norms = np.linalg.norm(rays_w, axis=1)
    if np.any(norms < 1e-6) or np.linalg.norm(uv_px[0] - uv_px[1]) < 2.0:
        return None
    rays_w /= norms[:, None]
    angle = math.acos(float(np.clip(rays_w[0] @ rays_w[1], -1, 1)))
    focal = focal_from_ray_angle(uv_px, angle, width_px, height_px)
    if focal is None:
        return None
    rays_c = np.column_stack([uv_px - [width_px / 2.0, height_px / 2.0], np.full(2, focal)])
    rays_c /= np.linalg.norm(rays_c, axis=1, keepdims=True)
    # Rotation aligning world rays onto camera rays (Kabsch with the two rays and their cross product).
    a = np.vstack([rays_w, np.cross(rays_w[0], rays_w[1])])
    b = np.vstack([rays_c, np.cross(rays_c[0], rays_c[1])])
    u, _, vt = np.linalg.svd(b.T @ a)
    R_cw = u @ np.diag([1, 1, np.sign(np.linalg.det(u @ vt))]) @ vt
    pan, tilt, _ = angles_from_rotation(R_cw)
    camera = Camera(focal, 0.0, pan, tilt, 0.0, np.asarray(position_w, float), width_px, height_px)
    return _pan_tilt_steps(camera, uv_px, np.asarray(points_w, dtype=float).reshape(2, 3), steps)


def _pan_tilt_steps(camera: Camera, uv_px: np.ndarray, points_w: np.ndarray, steps: int) -> Camera | None:
    """Gauss-Newton steps on (pan, tilt) of ``camera`` (roll, f, k1, C held) bringing points_w onto uv_px.

    Args:
        uv_px: (N, 2) pixels; points_w: (N, 3) metres. The Jacobian is the analytic one of
            :func:`project_state` (state columns 2 = pan, 3 = tilt).

    Returns:
        The camera, or None when a point falls behind it.
    """
    W, H = camera.width_px, camera.height_px
    state = camera.to_vector()
    for _ in range(steps):
        uv, J_uv, front = project_state(state, points_w, W, H)
        if not front.all():
            return None
        residual = (uv_px - uv).ravel()
        J = J_uv.reshape(-1, 8)[:, 2:4]
        step, *_ = np.linalg.lstsq(J, residual, rcond=None)
        state[2:4] += np.clip(step, -0.2, 0.2)
        if np.max(np.abs(step)) < 1e-9:
            break
    _, _, front = project_state(state, points_w, W, H)
    return Camera.from_vector(state, W, H) if front.all() else None


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
    pairs of keypoints give cameras (:func:`camera_from_two_points`), scored by the keypoints
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
    per_position = []
    for position in positions:
        best = None
        for i, j in pairs:
            camera = camera_from_two_points(uv_px[[i, j]], points_w[[i, j]], position, width_px, height_px)
            if camera is None:
                continue
            key, _ = _score(camera, uv_px, points_w, inlier_px)
            if best is None or key > best[0]:
                best = (key, camera, position)
        if best is not None:
            per_position.append(best)
    if not per_position:
        return ReinitResult(None, None, "", "no keypoint pair gave a camera", len(pairs))
    # The most promising hypotheses are refined on their inliers (loose, then tight) and re-scored.
    per_position.sort(key=lambda item: item[0], reverse=True)
    best = None
    for _, camera, position in per_position[:refine_top]:
        # A focal point metres off shifts the far keypoints in proportion to f: start loose.
        for threshold in (max(4.0 * inlier_px, loose_per_focal * camera.focal_px), 2.0 * inlier_px, inlier_px):
            _, inliers = _score(camera, uv_px, points_w, threshold)
            if inliers.sum() >= 3:
                camera = _refine_on_keypoints(camera, uv_px[inliers], points_w[inliers], np.asarray(position, float))
        key, _ = _score(camera, uv_px, points_w, inlier_px)
        if best is None or key > best[0]:
            best = (key, camera, position)
    _, camera, position = best
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
