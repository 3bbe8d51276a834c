"""Broadcast camera motion on a tripod: presets and camera tracks for synthetic clips.

A camera operator on a fluid head follows play. The model (the tripod model of
:mod:`broadtrack_graph.geometry.tripod`):

* The pan and tilt axes meet at a fixed point T_w and the optical axis passes at a fixed
  offset delta from it, for the whole clip; the focal point slides along the optical axis
  with zoom: ``C = T - delta r2 + lambda r3``, with r_i the columns of ``R_cw^T`` (r3 the
  optical axis) and lambda the slide along it, metres (exact for every generated frame).
* Play is a ball path on the pitch: dribbles (a few m/s), pauses and long passes
  (fast sweeps). The operator's aim point follows the ball through a critically damped
  second-order filter (the fluid head), so pan and tilt are smooth; small operator
  jitter is added.
* Zoom (horizontal field of view) drifts between the preset's limits, opens when play
  is fast, and now and then the operator zooms in on a player in an area with few
  markings (between the penalty area and the centre circle).
* A preset with ``max_view_speed_fov_per_s`` has its operator open the zoom ahead of a sweep,
  so that the view turns by at most that many fields of view per second (a whip pan is shot
  wide, a tight view only drifts); the zoom closes again at its own pace afterwards.
* f follows the field of view, ``f = (W / 2) / tan(hfov / 2)``; k1 and lambda are
  smooth functions of f (the entrance pupil moves forward when zooming in; k1 is
  largest at wide angle and small at tele).
* k1 is kept >= 0 in the presets on purpose. With k1 < 0 the model
  ``r (1 + k1 r^2)`` folds points far off the optical axis (beyond ~75-88 deg for
  k1 = -0.08..-0.001) back into the image, mirrored; the SoccerNet metric projects
  the template with that model, so such a camera "sees" pitch classes that no pixel
  shows, and even the ground-truth camera would score below 1.0 against honest
  annotations in most main-camera frames. A positive k1 (pincushion) is monotonic.
* Roll is a tiny constant (tripod levelling error).

Angles follow the SoccerNet convention of :mod:`broadtrack_graph.geometry.camera` (pan 0 looks
towards -y, tilt 90 deg is horizontal, z down). No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.ndimage import gaussian_filter1d

from broadtrack_graph.geometry.camera import Camera, rotation_from_angles
from broadtrack_graph.geometry.tripod import Tripod, focal_point
from broadtrack_graph.synth.presets import PRESET_STREAMS, MotionPreset, get_preset

FPS = 25.0
"""Frame rate of the generated tracks (frames per second)."""

HALF_LENGTH_M = 52.5
HALF_WIDTH_M = 34.0


@dataclass
class CameraTrack:
    """A generated camera track.

    cameras: one Camera per frame at (width_px, height_px), exactly on the tripod.
    tripod: the fixed tripod (T_w, delta_m).
    lambdas_m: (frame_count,) lambda of each frame (metres along the optical axis).
    fps: frames per second.
    preset: preset name.
    ball_w: (frame_count, 3) the play (ball) position the operator follows, metres, z = 0.
    """

    cameras: list[Camera]
    tripod: Tripod
    lambdas_m: np.ndarray
    fps: float
    preset: str
    ball_w: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.cameras)


# --------------------------------------------------------------------------- zoom laws


def hfov_to_focal_px(hfov_rad, width_px: int):
    """Focal length (pixels at width_px) for a horizontal field of view (radians)."""
    return (width_px / 2.0) / np.tan(np.asarray(hfov_rad) / 2.0)


def zoom_fraction(preset: MotionPreset, focal_px, width_px: int):
    """0 at the preset's widest zoom, 1 at its tightest (log focal length), clipped to [0, 1]."""
    lo_deg, hi_deg = preset.hfov_range_deg
    f_wide = hfov_to_focal_px(math.radians(hi_deg), width_px)
    f_tele = hfov_to_focal_px(math.radians(lo_deg), width_px)
    frac = (np.log(np.asarray(focal_px, dtype=float)) - math.log(f_wide)) / (math.log(f_tele) - math.log(f_wide))
    return np.clip(frac, 0.0, 1.0)


def k1_from_focal(preset: MotionPreset, focal_px, width_px: int):
    """k1 as a smooth function of the focal length: k1_wide at wide angle, k1_tele at tele."""
    frac = zoom_fraction(preset, focal_px, width_px)
    return preset.k1_tele + (preset.k1_wide - preset.k1_tele) * (1.0 - frac) ** 2


def lambda_from_focal(preset: MotionPreset, focal_px, width_px: int):
    """lambda (metres): the focal point moves forward along the optical axis when zooming in."""
    frac = zoom_fraction(preset, focal_px, width_px)
    return preset.lambda_wide_m + (preset.lambda_tele_m - preset.lambda_wide_m) * frac


# --------------------------------------------------------------------------- play and operator


def _ball_path(preset: MotionPreset, frame_count: int, rng: np.random.Generator):
    """(frame_count, 2) ball positions (x, y metres) and (frame_count,) speeds (m/s)."""
    dt = 1.0 / FPS
    (x_lo, x_hi), (y_lo, y_hi) = preset.ball_x_range_m, preset.ball_y_range_m
    position = np.array([rng.uniform(x_lo, x_hi), rng.uniform(y_lo, y_hi)])
    path = np.empty((frame_count, 2))
    speeds = np.empty(frame_count)
    t = 0
    while t < frame_count:
        event = rng.random()
        if event < preset.pause_probability:
            steps = int(rng.uniform(0.5, 2.0) * FPS)
            path[t:t + steps] = position
            speeds[t:t + steps] = 0.0
            t += steps
            continue
        if event < preset.pause_probability + preset.pass_probability:
            speed = rng.uniform(*preset.pass_speed_mps)
            distance = rng.uniform(20.0, 55.0)
        else:
            speed = rng.uniform(*preset.dribble_speed_mps)
            distance = rng.uniform(4.0, 18.0)
        angle = rng.uniform(0, 2 * math.pi)
        target = position + distance * np.array([math.cos(angle), math.sin(angle)])
        target = np.array([np.clip(target[0], x_lo, x_hi), np.clip(target[1], y_lo, y_hi)])
        length = float(np.linalg.norm(target - position))
        steps = max(1, int(length / (speed * dt)))
        fractions = np.arange(1, steps + 1) / steps
        # Ease in and out so that the ball accelerates and decelerates.
        eased = 0.5 - 0.5 * np.cos(math.pi * fractions)
        chunk = position + eased[:, None] * (target - position)
        end = min(frame_count, t + steps)
        path[t:end] = chunk[: end - t]
        speeds[t:end] = length / (steps * dt)
        position = target
        t = end
    return path, speeds


def _second_order_filter(signal: np.ndarray, time_constant_s: float, initial=None) -> np.ndarray:
    """Critically damped second-order low-pass of a (N, D) signal sampled at FPS (a fluid head)."""
    dt = 1.0 / FPS
    omega = 1.0 / max(time_constant_s, 1e-3)
    out = np.empty_like(signal)
    x = signal[0].copy() if initial is None else np.asarray(initial, dtype=float).copy()
    v = np.zeros_like(x)
    substeps = 4  # semi-implicit Euler, sub-stepped for stability at short time constants
    h = dt / substeps
    for i in range(len(signal)):
        for _ in range(substeps):
            v += h * (omega * omega * (signal[i] - x) - 2.0 * omega * v)
            x = x + h * v
        out[i] = x
    return out


def smooth_noise(key: tuple[int, ...], count: int, dims: int, sigma_frames: float) -> np.ndarray:
    """(count, dims) zero-mean, unit-variance Gaussian-smoothed noise that is prefix-stable.

    The raw white noise is drawn in blocks of 256 frames, each block from its own seeded
    generator, and padded beyond ``count`` by 4 sigma before smoothing, so frame i does
    not depend on ``count``: a short clip is the beginning of a long one.
    """
    sigma = max(1.0, float(sigma_frames))
    total = count + int(math.ceil(4 * sigma)) + 1
    blocks = [np.random.default_rng([*key, b]).standard_normal((256, dims)) for b in range((total + 255) // 256)]
    raw = np.concatenate(blocks)[:total]
    smooth = gaussian_filter1d(raw, sigma, axis=0, mode="reflect", truncate=4.0)
    # Gaussian smoothing of unit white noise leaves a variance of 1 / (2 sqrt(pi) sigma).
    return smooth[:count] * math.sqrt(2.0 * math.sqrt(math.pi) * sigma)


def _operator_plan(preset: MotionPreset, ball_xy: np.ndarray, speeds: np.ndarray, rng: np.random.Generator,
                   noise_key: tuple[int, ...]):
    """Desired aim points (N, 2) and desired horizontal fields of view (N,) radians."""
    count = len(ball_xy)
    aim = ball_xy.copy()
    aim[:, 1] += preset.aim_offset_y_m * np.sign(preset.tripod_T_w[1]) if preset.tripod_T_w[1] != 0 else 0.0
    lo, hi = (math.radians(v) for v in preset.hfov_range_deg)
    typical = math.radians(preset.hfov_typical_deg)
    # Slow zoom drift around the typical field of view, opening with play speed.
    drift = smooth_noise(noise_key, count, 1, 3.0 * FPS)[:, 0]
    speed_open = np.clip(speeds / max(preset.pass_speed_mps[1], 1e-6), 0.0, 1.0)
    log_hfov = math.log(typical) + 0.25 * drift + 0.35 * speed_open
    hfov = np.clip(np.exp(log_hfov), lo, hi)
    # Zoom-ins on sparse areas (few markings): between the penalty area and the centre circle.
    rate_per_frame = preset.sparse_zoom_per_min / (60.0 * FPS)
    t = int(rng.exponential(1.0 / rate_per_frame)) if rate_per_frame > 0 else count
    while t < count:
        duration = int(rng.uniform(*preset.sparse_zoom_duration_s) * FPS)
        x_lo, x_hi = preset.ball_x_range_m
        side = rng.choice([-1.0, 1.0])
        x = side * rng.uniform(14.0, 30.0)
        if not x_lo <= x <= x_hi:
            x = -x if x_lo <= -x <= x_hi else np.clip(0.5 * (x_lo + x_hi) + rng.uniform(-8, 8), x_lo, x_hi)
        y = rng.uniform(-22.0, 22.0)
        end = min(count, t + duration)
        walk = np.cumsum(rng.normal(0.0, 0.04, size=(end - t, 2)), axis=0)  # the player moves a little
        aim[t:end] = np.array([x, y]) + walk
        hfov[t:end] = math.radians(rng.uniform(*preset.sparse_zoom_hfov_deg))
        t = end + int(rng.exponential(1.0 / rate_per_frame))
    return aim, hfov


def _look_ahead_frames(preset: MotionPreset) -> int:
    """Frames the operator sees a sweep coming: long enough to open the lens over its whole range
    (:func:`_zoom_rate_per_frame`) and for the zoom to catch up (four zoom time constants)."""
    lo, hi = preset.hfov_range_deg
    crossing = math.log(math.tan(math.radians(hi) / 2) / math.tan(math.radians(lo) / 2)) / _zoom_rate_per_frame(preset)
    return int(math.ceil(crossing + 4.0 * preset.zoom_time_s * FPS))


def _zoom_rate_per_frame(preset: MotionPreset) -> float:
    """How fast the operator opens the zoom ahead of a sweep: the lens's whole range (log focal length) in four
    zoom time constants, per frame."""
    lo, hi = preset.hfov_range_deg
    span = math.log(math.tan(math.radians(hi) / 2) / math.tan(math.radians(lo) / 2))
    return span / (4.0 * preset.zoom_time_s * FPS)


def _sweep_focal_limit(preset: MotionPreset, pan_rad: np.ndarray, tilt_rad: np.ndarray, width_px: int) -> np.ndarray:
    """(N,) the largest log focal length (pixels at width_px) the operator aims the zoom at so that the view turns
    by at most ``preset.max_view_speed_fov_per_s`` fields of view per second, opened ahead of each sweep.

    The optical axis turns at ``hypot(sin(tilt) d pan, d tilt)`` radians per frame. Each frame's own limit is
    moved four zoom time constants earlier (the zoom, starting from rest, reaches its aim about that much later), then the largest function
    below it that changes by at most :func:`_zoom_rate_per_frame` a frame is taken (the lens opens over many
    frames, never in a snap).
    """
    axis_speed = np.hypot(np.sin(tilt_rad) * np.gradient(pan_rad), np.gradient(tilt_rad)) * FPS  # rad/s
    lo, hi = (math.radians(v) for v in preset.hfov_range_deg)
    own = np.log(hfov_to_focal_px(np.clip(axis_speed / preset.max_view_speed_fov_per_s, lo, hi), width_px))
    lag = int(round(4.0 * preset.zoom_time_s * FPS))
    padded = np.concatenate([own, np.full(lag, own[-1])])
    limit = sliding_window_view(padded, lag + 1).min(axis=1)
    rate = _zoom_rate_per_frame(preset)
    for i in range(1, len(limit)):  # limit[t] = min over s of own_ahead[s] + rate |s - t|: two passes
        limit[i] = min(limit[i], limit[i - 1] + rate)
    for i in range(len(limit) - 2, -1, -1):
        limit[i] = min(limit[i], limit[i + 1] + rate)
    return limit


def _aim_angles(T_w: np.ndarray, aim_xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pan and tilt (radians) whose optical axis from T_w passes through ground points aim_xy (N, 2)."""
    direction = np.column_stack([aim_xy[:, 0] - T_w[0], aim_xy[:, 1] - T_w[1], np.full(len(aim_xy), -T_w[2])])
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    # Optical axis = (sin p sin t, -cos p sin t, cos t).
    tilt = np.arccos(np.clip(direction[:, 2], -1.0, 1.0))
    pan = np.arctan2(direction[:, 0], -direction[:, 1])
    return pan, tilt


def generate_camera_track(preset: str, frame_count: int, width_px: int, height_px: int, seed: int = 0) -> CameraTrack:
    """A smooth broadcast camera track on a fixed tripod.

    Args:
        preset: one of PRESETS ("main", "16m", "high-behind", "hard", "wide", "long", "low", "low-16m", "fast").
        frame_count: number of frames (>= 1), at FPS = 25.
        width_px, height_px: image size of the cameras.
        seed: random seed; the same arguments always give the same track.

    Returns:
        CameraTrack whose cameras satisfy ``C = T - delta r2 + lambda r3`` exactly
        (to float rounding), with f, k1 and lambda tied to the zoom.

    Raises:
        ValueError: unknown preset, frame_count < 1 or a non-positive image size.
    """
    spec = get_preset(preset)
    if frame_count < 1:
        raise ValueError(f"frame_count must be >= 1, got {frame_count}")
    if width_px <= 0 or height_px <= 0:
        raise ValueError(f"image size must be positive, got {width_px}x{height_px}")
    # Separate random streams per component keep a short clip the beginning of a long one; a zoom opened ahead
    # of sweeps looks ahead, so play is generated that far beyond the clip's end and cut off.
    key = (int(seed), PRESET_STREAMS.index(preset))
    T_w = np.asarray(spec.tripod_T_w, dtype=float)
    tripod = Tripod(tuple(float(v) for v in T_w), float(spec.delta_m))
    planned = frame_count + (0 if spec.max_view_speed_fov_per_s is None else 2 * _look_ahead_frames(spec) + 1)

    ball_xy, speeds = _ball_path(spec, planned, np.random.default_rng([*key, 1]))
    aim_xy, hfov_rad = _operator_plan(spec, ball_xy, speeds, np.random.default_rng([*key, 3]), (*key, 2))
    aim_xy[:, 0] = np.clip(aim_xy[:, 0], *spec.aim_x_range_m)
    aim_xy[:, 1] = np.clip(aim_xy[:, 1], *spec.aim_y_range_m)
    aim_xy = _second_order_filter(aim_xy, spec.follow_time_s)
    pan, tilt = _aim_angles(T_w, aim_xy)
    log_focal_plan = np.log(hfov_to_focal_px(hfov_rad, width_px))
    if spec.max_view_speed_fov_per_s is not None:  # opened ahead of sweeps
        log_focal_plan = np.minimum(log_focal_plan, _sweep_focal_limit(spec, pan, tilt, width_px))
    log_focal = _second_order_filter(log_focal_plan[:, None], spec.zoom_time_s)[:, 0]
    pan, tilt, log_focal, ball_xy = pan[:frame_count], tilt[:frame_count], log_focal[:frame_count], ball_xy[:frame_count]
    focal_px = np.exp(log_focal)

    jitter = np.radians(spec.jitter_deg) * smooth_noise((*key, 4), frame_count, 2, 2.0)
    pan = pan + jitter[:, 0]
    tilt = tilt + jitter[:, 1]
    roll = math.radians(np.random.default_rng([*key, 5]).uniform(-spec.roll_max_deg, spec.roll_max_deg))

    k1 = k1_from_focal(spec, focal_px, width_px)
    lambdas = np.asarray(lambda_from_focal(spec, focal_px, width_px), dtype=float)
    cameras = []
    for i in range(frame_count):
        R_cw = rotation_from_angles(float(pan[i]), float(tilt[i]), roll)
        C_w = focal_point(R_cw, tripod, float(lambdas[i]))
        cameras.append(Camera(float(focal_px[i]), float(k1[i]), float(pan[i]), float(tilt[i]), roll, C_w, width_px, height_px))
    ball_w = np.column_stack([ball_xy, np.zeros(frame_count)])
    return CameraTrack(cameras=cameras, tripod=tripod, lambdas_m=lambdas, fps=FPS, preset=preset, ball_w=ball_w)


def pitch_coverage(camera: Camera, grid: int = 24, margin_m: float = 3.0) -> float:
    """Share of the image (0..1) whose pixels see the ground inside the pitch plus margin_m.

    Evaluated on a grid x grid lattice of pixel centres.
    """
    u = (np.arange(grid) + 0.5) * camera.width_px / grid
    v = (np.arange(grid) + 0.5) * camera.height_px / grid
    uu, vv = np.meshgrid(u, v)
    points_w, hits = camera.ground_intersection(np.column_stack([uu.ravel(), vv.ravel()]))
    with np.errstate(invalid="ignore"):
        inside = hits & (np.abs(points_w[:, 0]) <= HALF_LENGTH_M + margin_m) & (np.abs(points_w[:, 1]) <= HALF_WIDTH_M + margin_m)
    return float(inside.mean())
