"""The two-point method, batched over pairs of keypoints: a roll-free camera at a known focal point from two pixels.

With the focal point at the tripod and roll 0, the angle between the rays of two keypoints gives f
(in closed form), and rotating the two world rays onto the two camera rays gives pan and tilt; a
few Gauss-Newton steps on (pan, tilt) then bring both points back once the roll is dropped. Every
pair of a frame's keypoints is solved at once (numpy over pairs), and scored on all the keypoints,
for :func:`~broadtrack_graph.reinit.keypoints.reinit_from_keypoints`' RANSAC.

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T`` (:mod:`broadtrack_graph.geometry.state`). No I/O.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.state import BEHIND_CAMERA_Z, angles_from_rotations


def focal_from_ray_angles(uv_pairs_px: np.ndarray, angles_rad: np.ndarray, width_px: int,
                          height_px: int) -> np.ndarray:
    """Focal lengths (pixels) at which the rays of pixel pairs make given angles, in closed form.

    With ``d1, d2`` the pixels' offsets from the image centre, the rays ``(d, f)`` make the angle
    t with ``cos t = (p + x) / sqrt((a + x)(b + x))``, where ``x = f^2``, ``a = |d1|^2``,
    ``b = |d2|^2`` and ``p = d1.d2``. Squared, this is the quadratic
    ``(1 - c^2) x^2 + (2p - c^2 (a + b)) x + p^2 - c^2 a b = 0`` (c = cos t), whose roots with
    ``p + x`` of the sign of c fit. As f grows the angle rises from the pixels' angle in the image
    plane (f -> 0), peaks (for pixels on one side of the centre) and falls to 0, so up to two
    focal lengths fit: the longer is given, on the falling side, where a broadcast lens is (a
    lens wide enough to be on the rising side is not searched for).

    Args:
        uv_pairs_px: (P, 2, 2) the two pixels of each pair.
        angles_rad: (P,) the angle each pair's rays must make.
        width_px, height_px: image size; the principal point is its centre.

    Returns:
        (P,) focal lengths; NaN where the angle cannot be reached with f in [0.05, 50] image widths.
    """
    d = np.asarray(uv_pairs_px, float).reshape(-1, 2, 2) - [width_px / 2.0, height_px / 2.0]
    c = np.cos(np.asarray(angles_rad, float).reshape(-1))
    a, b = np.einsum("pi,pi->p", d[:, 0], d[:, 0]), np.einsum("pi,pi->p", d[:, 1], d[:, 1])
    p = np.einsum("pi,pi->p", d[:, 0], d[:, 1])
    qa, qb, qc = 1.0 - c * c, 2.0 * p - c * c * (a + b), p * p - c * c * a * b
    lo, hi = (0.05 * width_px) ** 2, (50.0 * width_px) ** 2
    focal = np.full(len(c), np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        root = np.sqrt(np.maximum(qb * qb - 4.0 * qa * qc, 0.0))
        for x in ((-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa)):
            cos_at_x = (p + x) / np.sqrt((a + x) * (b + x))
            ok = np.isnan(focal) & (x >= lo) & (x <= hi) & (np.abs(cos_at_x - c) < 1e-9 * (1.0 + np.abs(c)))
            focal[ok] = np.sqrt(x[ok])
    return focal


def _roll_free_rotations(pan_rad: np.ndarray, tilt_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(P, 3, 3) world-to-camera rotations ``(Rz(pan) Rx(tilt))^T`` (roll 0) and their derivatives with respect to
    pan and tilt (each (P, 3, 3))."""
    cp, sp, ct, st = np.cos(pan_rad), np.sin(pan_rad), np.cos(tilt_rad), np.sin(tilt_rad)
    zero = np.zeros_like(cp)
    R = np.stack([np.stack([cp, sp, zero], -1), np.stack([-sp * ct, cp * ct, st], -1),
                  np.stack([sp * st, -cp * st, ct], -1)], -2)
    dR_dpan = np.stack([np.stack([-sp, cp, zero], -1), np.stack([-cp * ct, -sp * ct, zero], -1),
                        np.stack([cp * st, sp * st, zero], -1)], -2)
    dR_dtilt = np.stack([np.stack([zero, zero, zero], -1), np.stack([sp * st, -cp * st, ct], -1),
                         np.stack([sp * ct, -cp * ct, -st], -1)], -2)
    return R, dR_dpan, dR_dtilt


def _project_roll_free(focal_px, pan_rad, tilt_rad, position_w, points_w, width_px: int, height_px: int,
                       want_jacobian: bool = False):
    """Project points with P roll-free, distortion-free cameras standing at one focal point.

    Args:
        focal_px, pan_rad, tilt_rad: (P,) the cameras.
        position_w: (3,) their focal point, metres.
        points_w: (P, K, 3) each camera's points, or (K, 3) the same points for all, metres.

    Returns:
        uv_px: (P, K, 2); in_front: (P, K) depth above 1 mm; with want_jacobian, d uv / d (pan, tilt) (P, K, 2, 2).
    """
    R, dR_dpan, dR_dtilt = _roll_free_rotations(pan_rad, tilt_rad)
    d_w = np.asarray(points_w, float) - np.asarray(position_w, float)
    d_w = np.broadcast_to(d_w, (len(R),) + d_w.shape[-2:])
    points_c = np.einsum("pij,pkj->pki", R, d_w)
    in_front = points_c[..., 2] > BEHIND_CAMERA_Z
    depth = np.where(in_front, points_c[..., 2], 1.0)
    xy_n = points_c[..., :2] / depth[..., None]
    f = np.asarray(focal_px, float)[:, None, None]
    uv_px = f * xy_n + [width_px / 2.0, height_px / 2.0]
    if not want_jacobian:
        return uv_px, in_front
    # d uv / d Xc = f / z [[1, 0, -x], [0, 1, -y]], times d Xc / d angle = dR (X - C).
    duv_dXc = np.zeros(xy_n.shape[:2] + (2, 3))
    duv_dXc[..., 0, 0] = duv_dXc[..., 1, 1] = 1.0
    duv_dXc[..., :, 2] = -xy_n
    duv_dXc *= (f[..., None] / depth[..., None, None])
    dXc = np.stack([np.einsum("pij,pkj->pki", dR_dpan, d_w), np.einsum("pij,pkj->pki", dR_dtilt, d_w)], -1)
    return uv_px, in_front, duv_dXc @ dXc


def two_point_cameras(uv_pairs_px: np.ndarray, point_pairs_w: np.ndarray, position_w, width_px: int,
                      height_px: int, steps: int = 4) -> np.ndarray:
    """The two-point method for P pairs at once: focal point fixed at position_w, roll 0, k1 0.

    Args:
        uv_pairs_px: (P, 2, 2) pixels of each pair of pitch points; point_pairs_w: (P, 2, 3) their positions (metres).
        position_w: (3,) focal point (the tripod T).
        steps: Gauss-Newton steps on (pan, tilt) once roll is set to 0.

    The rotation that carries a pair's two world rays onto its two camera rays (f from their angle,
    :func:`focal_from_ray_angles`) gives pan and tilt; dropping its roll moves the points, so a few
    Gauss-Newton steps on (pan, tilt) alone then bring the two points back (least squares over both,
    each step at most 0.2 rad). Sign facts, for a camera looking down at the pitch: +pan moves points
    towards -u by about f sin(tilt) per radian, +tilt moves them towards +v by about f per radian.

    Returns:
        (P, 3) ``[f, pan, tilt]`` (pixels, radians); NaN rows where the pair is degenerate (points on the focal
        point or under 2 px apart, or not numbers), the angle cannot be matched, or a point falls behind the camera.
    """
    uv = np.asarray(uv_pairs_px, float).reshape(-1, 2, 2)
    points = np.asarray(point_pairs_w, float).reshape(-1, 2, 3)
    position = np.asarray(position_w, float).reshape(3)
    finite = np.isfinite(uv).all(axis=(1, 2)) & np.isfinite(points).all(axis=(1, 2))
    uv = np.where(finite[:, None, None], uv, [[0.0, 0.0], [100.0, 0.0]])  # stand-ins, dropped below
    points = np.where(finite[:, None, None], points, [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    rays_w = points - position
    norms = np.linalg.norm(rays_w, axis=2)
    ok = finite & np.all(norms >= 1e-6, axis=1) & (np.linalg.norm(uv[:, 0] - uv[:, 1], axis=1) >= 2.0)
    rays_w = rays_w / np.where(norms >= 1e-6, norms, 1.0)[..., None]
    angles = np.arccos(np.clip(np.einsum("pi,pi->p", rays_w[:, 0], rays_w[:, 1]), -1.0, 1.0))
    focal = np.where(ok, focal_from_ray_angles(uv, angles, width_px, height_px), np.nan)
    ok &= np.isfinite(focal)
    f = np.where(ok, focal, 1.0)
    rays_c = np.concatenate([uv - [width_px / 2.0, height_px / 2.0], np.broadcast_to(f[:, None, None], (len(f), 2, 1))],
                            axis=2)
    rays_c /= np.linalg.norm(rays_c, axis=2, keepdims=True)
    # Rotations aligning world rays onto camera rays (Kabsch with the two rays and their cross product).
    a = np.concatenate([rays_w, cross3(rays_w[:, 0], rays_w[:, 1])[:, None]], axis=1)
    b = np.concatenate([rays_c, cross3(rays_c[:, 0], rays_c[:, 1])[:, None]], axis=1)
    u, _, vt = np.linalg.svd(np.einsum("pki,pkj->pij", b, a))
    u[:, :, 2] *= np.sign(np.linalg.det(u @ vt))[:, None]
    angles = angles_from_rotations(u @ vt)  # the roll is dropped
    pan, tilt = angles[:, 0], angles[:, 1]
    pan, tilt, front = _pan_tilt_steps(f, pan, tilt, position, uv, points, width_px, height_px, steps)
    ok &= front
    return np.where(ok[:, None], np.stack([focal, pan, tilt], axis=1), np.nan)


def _pan_tilt_steps(focal_px, pan_rad, tilt_rad, position_w, uv_px, points_w, width_px: int, height_px: int,
                    steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss-Newton steps on (pan, tilt) of P roll-free cameras (f and the focal point held) bringing each one's
    points onto its pixels (least squares, each step at most 0.2 rad).

    Args:
        focal_px, pan_rad, tilt_rad: (P,); position_w: (3,) metres.
        uv_px: (P, K, 2) pixels; points_w: (P, K, 3) metres.

    Returns:
        (pan (P,), tilt (P,), every point in front of the camera at every step (P,) bool).
    """
    uv_px = np.asarray(uv_px, float)
    pan, tilt = np.array(pan_rad, float), np.array(tilt_rad, float)
    ok = np.ones(len(pan), bool)
    for _ in range(steps):
        uv, front, J = _project_roll_free(focal_px, pan, tilt, position_w, points_w, width_px, height_px,
                                          want_jacobian=True)
        ok &= front.all(axis=1)
        step = np.einsum("pij,pj->pi", np.linalg.pinv(J.reshape(len(pan), -1, 2)), (uv_px - uv).reshape(len(pan), -1))
        step = np.where(ok[:, None], np.clip(step, -0.2, 0.2), 0.0)
        pan, tilt = pan + step[:, 0], tilt + step[:, 1]
    _, front = _project_roll_free(focal_px, pan, tilt, position_w, points_w, width_px, height_px)
    return pan, tilt, ok & front.all(axis=1)


def pair_scores(cameras: np.ndarray, position_w, uv_px: np.ndarray, points_w: np.ndarray, width_px: int,
                 height_px: int, inlier_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Each two-point camera scored on all keypoints: (inlier count (P,), minus the sum of errors capped at
    inlier_px (P,)); NaN cameras score (-1, -inf).

    Args:
        cameras: (P, 3) ``[f, pan, tilt]`` of :func:`two_point_cameras`; uv_px (N, 2), points_w (N, 3).
    """
    ok = np.isfinite(cameras).all(axis=1)
    safe = np.where(ok[:, None], cameras, [1.0, 0.0, 0.0])
    uv, front = _project_roll_free(safe[:, 0], safe[:, 1], safe[:, 2], position_w, points_w, width_px, height_px)
    err = np.linalg.norm(uv - uv_px, axis=2)
    err = np.where(front & np.isfinite(err), err, np.inf)  # behind the camera, or a keypoint that is not a number
    count = np.where(ok, (err < inlier_px).sum(axis=1), -1)
    capped = np.where(ok, -np.minimum(err, inlier_px).sum(axis=1), -np.inf)
    return count, capped
