"""Synthetic observations for tests and benchmarks of the graph (no images).

From a camera track: ground-truth projections of the pitch markings and keypoints
plus Gaussian pixel noise and gross outliers, and optical-flow matches between
consecutive frames (ground points seen by both cameras). Seeded and deterministic.
No I/O.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.types.observations import FlowMatches, FrameObservations, KeypointObservations


@dataclass(frozen=True)
class SimulationSettings:
    """What the synthetic front end produces per frame."""

    line_points: int = 300  # line/circle points per frame (fewer when less is visible)
    flow_matches: int = 700  # flow matches per frame (from frame 1 on)
    keypoints: int = 0  # at most this many visible pitch keypoints per frame
    noise_px: float = 1.0  # Gaussian noise per coordinate, pixels
    outlier_ratio: float = 0.1  # share of measurements replaced by gross outliers
    flow_outlier_px: float = 40.0  # outlier flow matches are displaced by up to this much
    sample_step_m: float = 0.1  # marking sampling before drawing the observed points
    ground_margin_m: float = 5.0  # flow points must lie within the pitch plus this margin


def simulate_frames(
    cameras: Sequence[Camera],
    pitch: PitchTemplate,
    settings: SimulationSettings | None = None,
    seed: int = 0,
    empty_frames: Sequence[int] = (),
) -> Iterator[FrameObservations]:
    """Yield one FrameObservations per camera (lazily, for long runs).

    Args:
        cameras: ground-truth cameras, one per frame, all at the same resolution.
        pitch: the pitch template.
        settings: counts, noise and outliers.
        seed: random seed.
        empty_frames: frame indices that get no observation at all (cut-aways); the frame
            after one gets no flow either.
    """
    settings = settings or SimulationSettings()
    rng = np.random.default_rng(seed)
    samples = pitch.sample_uniform(settings.sample_step_m)
    names = [n for n in LINE_CLASSES if n in samples]
    points_w = np.vstack([samples[n] for n in names])
    class_of = np.concatenate([np.full(len(samples[n]), i) for i, n in enumerate(names)])
    kp_names = list(pitch.keypoints)
    kp_w = pitch.keypoint_array(kp_names)
    half_l = pitch.dimensions.length_m / 2 + settings.ground_margin_m
    half_w = pitch.dimensions.width_m / 2 + settings.ground_margin_m
    empty = set(int(i) for i in empty_frames)
    for t, camera in enumerate(cameras):
        W, H = camera.width_px, camera.height_px
        if t in empty:
            yield FrameObservations(t, W, H)
            continue
        lines = _line_points(camera, points_w, class_of, names, settings, rng)
        keypoints = _keypoints(camera, kp_w, kp_names, settings, rng) if settings.keypoints > 0 else None
        flow = None
        if t > 0 and (t - 1) not in empty and settings.flow_matches > 0:
            flow = _flow(cameras[t - 1], camera, half_l, half_w, settings, rng)
        yield FrameObservations(t, W, H, lines_px=lines, keypoints=keypoints, flow=flow)


def visible_mask(camera: Camera, points_w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project points and flag the ones really seen: in front, inside the image, and within the
    radius where the radial distortion is monotonic (beyond it a negative k1 folds far-away
    points back into the image, which no real lens does).

    Returns:
        uv_px (N, 2), visible (N,) bool.
    """
    uv, in_front = camera.project(points_w)
    points_c = camera.world_to_camera(points_w)
    depth = np.where(in_front, points_c[:, 2], 1.0)
    r2 = (points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / depth**2
    monotonic = 1.0 + 3.0 * camera.k1 * r2 > 0.05
    return uv, in_front & monotonic & camera.in_image(uv)


def _noisy_with_outliers(uv: np.ndarray, camera: Camera, settings: SimulationSettings, rng) -> np.ndarray:
    uv = uv + rng.normal(0.0, settings.noise_px, uv.shape)
    outliers = rng.random(len(uv)) < settings.outlier_ratio
    uv[outliers] = rng.uniform([0, 0], [camera.width_px, camera.height_px], (int(outliers.sum()), 2))
    return uv


def _line_points(camera, points_w, class_of, names, settings, rng) -> dict[str, np.ndarray]:
    uv, seen = visible_mask(camera, points_w)
    visible = np.flatnonzero(seen)
    if len(visible) == 0:
        return {}
    chosen = rng.choice(visible, size=min(settings.line_points, len(visible)), replace=False)
    uv_obs = _noisy_with_outliers(uv[chosen], camera, settings, rng)
    out: dict[str, np.ndarray] = {}
    for j in np.unique(class_of[chosen]):
        out[names[j]] = uv_obs[class_of[chosen] == j]
    return out


def _keypoints(camera, kp_w, kp_names, settings, rng) -> KeypointObservations | None:
    uv, seen = visible_mask(camera, kp_w)
    visible = np.flatnonzero(seen)
    if len(visible) == 0:
        return None
    chosen = rng.choice(visible, size=min(settings.keypoints, len(visible)), replace=False)
    uv_obs = _noisy_with_outliers(uv[chosen], camera, settings, rng)
    return KeypointObservations(uv_obs, kp_w[chosen], np.ones(len(chosen)), [kp_names[i] for i in chosen])


def _flow(previous: Camera, camera: Camera, half_l, half_w, settings, rng) -> FlowMatches | None:
    W, H = camera.width_px, camera.height_px
    candidates = rng.uniform([0, 0], [W, H], (3 * settings.flow_matches, 2))
    ground, hits = previous.ground_intersection(candidates)
    inside = hits & (np.abs(ground[:, 0]) < half_l) & (np.abs(ground[:, 1]) < half_w)
    uv_cur, seen = visible_mask(camera, np.where(inside[:, None], ground, 0.0))
    keep = np.flatnonzero(inside & seen)[: settings.flow_matches]
    if len(keep) == 0:
        return None
    uv_prev = candidates[keep]
    uv_next = uv_cur[keep] + rng.normal(0.0, settings.noise_px, (len(keep), 2))
    outliers = rng.random(len(keep)) < settings.outlier_ratio
    uv_next[outliers] += rng.uniform(-settings.flow_outlier_px, settings.flow_outlier_px, (int(outliers.sum()), 2))
    return FlowMatches(uv_prev, uv_next)


def perturb_camera(camera: Camera, rng: np.random.Generator, angle_deg: float = 2.0, focal_rel: float = 0.15, position_m: float = 1.0, k1_abs: float = 0.0) -> Camera:
    """A camera a few degrees / some percent of focal length / metres off (for refinement tests)."""
    return camera.replace(
        focal_px=camera.focal_px * (1.0 + rng.uniform(-focal_rel, focal_rel)),
        k1=camera.k1 + rng.uniform(-k1_abs, k1_abs),
        pan_rad=camera.pan_rad + np.radians(rng.uniform(-angle_deg, angle_deg)),
        tilt_rad=camera.tilt_rad + np.radians(rng.uniform(-angle_deg, angle_deg)),
        roll_rad=camera.roll_rad + np.radians(rng.uniform(-angle_deg, angle_deg) * 0.25),
        position_m=camera.position_m + rng.uniform(-position_m, position_m, 3),
    )


def reprojection_error_px(estimate: Camera, truth: Camera, pitch: PitchTemplate, step_m: float = 1.0) -> float:
    """Mean pixel distance between the pitch markings projected by two cameras.

    Over the marking points (every ``step_m``) that the true camera really sees
    (:func:`visible_mask`); NaN when it sees none, inf when the estimate puts one behind it.
    """
    samples = pitch.sample_uniform(step_m)
    points_w = np.vstack(list(samples.values()))
    uv_true, keep = visible_mask(truth, points_w)
    if not keep.any():
        return float("nan")
    uv_est, front_est = estimate.project(points_w[keep])
    d = np.linalg.norm(uv_est - uv_true[keep], axis=1)
    d[~front_est] = np.inf
    return float(np.mean(d))
