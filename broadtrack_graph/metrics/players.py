"""Numbers from player positions on the pitch: distance covered, top speed, jitter, errors against the truth.

Per track (a track id over frames), positions are first smoothed lightly over time:
a centred moving average of ``smooth_frames`` frames (default 5, 0.2 s at 25 fps),
taken within each run of consecutive frames (a gap ends a run; the window shrinks
symmetrically at a run's ends). This is the usual
treatment of tracking data before speeds are read from it; raw frame-to-frame steps
add the positions' noise to every step and inflate distances.

* distance covered: the sum of the smoothed steps between consecutive frames (gaps of
  more than ``max_gap_frames`` are not bridged; shorter ones by the straight line);
* top speed: the largest displacement of the smoothed positions over ``speed_frames``
  frames (default 5) divided by that time, in m/s;
* jitter: the RMS of the second difference of the RAW positions over three consecutive
  frames, metres (a player's true motion at 25 fps contributes about 0.01 m: 7 m/s^2
  times (1/25 s)^2), so this is mostly the positions' frame-to-frame noise.

Tracks with an unknown id (-1) are left out of the per-track numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

DEFAULT_SMOOTH_FRAMES = 5
DEFAULT_SPEED_FRAMES = 5
DEFAULT_MAX_GAP_FRAMES = 5


@dataclass(frozen=True)
class AnalyticsConfig:
    """How positions become distances and speeds."""

    fps: float = 25.0  # frames per second of the clip
    smooth_frames: int = DEFAULT_SMOOTH_FRAMES  # centred moving-average window (frames; 1 = no smoothing)
    speed_frames: int = DEFAULT_SPEED_FRAMES  # displacement window of the top speed (frames)
    max_gap_frames: int = DEFAULT_MAX_GAP_FRAMES  # longer gaps in a track are not bridged for the distance


def fps_from_times(times_s: np.ndarray, frames: np.ndarray, default: float = 25.0) -> float:
    """Frames per second from per-frame times (seconds, NaN unknown) and frame indices: 1 / median step, else default."""
    times = np.asarray(times_s, dtype=float)
    frames = np.asarray(frames, dtype=float)
    ok = np.isfinite(times)
    if ok.sum() >= 2:
        dt = np.diff(times[ok]) / np.maximum(np.diff(frames[ok]), 1)
        dt = dt[dt > 0]
        if len(dt):
            return float(1.0 / np.median(dt))
    return default


def tracks(frames: np.ndarray, track_ids: np.ndarray, xy_m: np.ndarray) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Group positions by track id: id -> (frames (K,) sorted, xy (K, 2) metres); rows without position or id dropped.

    A track seen twice in a frame keeps the first row of that frame.
    """
    frames = np.asarray(frames, dtype=int)
    track_ids = np.asarray(track_ids, dtype=int)
    xy_m = np.asarray(xy_m, dtype=float).reshape(-1, 2)
    keep = np.isfinite(xy_m).all(axis=1) & (track_ids >= 0)
    out = {}
    for tid in np.unique(track_ids[keep]):
        rows = np.flatnonzero(keep & (track_ids == tid))
        order = rows[np.argsort(frames[rows], kind="stable")]
        f = frames[order]
        first = np.concatenate([[True], np.diff(f) > 0])
        out[int(tid)] = (f[first], xy_m[order][first])
    return out


def _runs(frames: np.ndarray, max_gap: int) -> list[slice]:
    """Slices of runs whose consecutive frames are at most max_gap apart."""
    if len(frames) == 0:
        return []
    breaks = np.flatnonzero(np.diff(frames) > max_gap) + 1
    edges = np.concatenate([[0], breaks, [len(frames)]])
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:])]


def smooth_track(frames: np.ndarray, xy_m: np.ndarray, window: int) -> np.ndarray:
    """Centred moving average of (K, 2) positions within runs of consecutive frames.

    Near the ends of a run the window shrinks symmetrically (the first and last points stay
    as they are), so motion at constant velocity is left unchanged.
    """
    out = np.array(xy_m, dtype=float, copy=True)
    if window <= 1:
        return out
    half = window // 2
    for run in _runs(frames, 1):
        seg = xy_m[run]
        n = len(seg)
        csum = np.vstack([np.zeros((1, 2)), np.cumsum(seg, axis=0)])
        k = np.arange(n)
        reach = np.minimum(np.minimum(half, k), n - 1 - k)
        lo, hi = k - reach, k + reach + 1
        out[run] = (csum[hi] - csum[lo]) / (hi - lo)[:, None]
    return out


def track_distance_m(frames: np.ndarray, xy_m: np.ndarray, max_gap: int) -> float:
    """Sum of steps between rows at most max_gap frames apart, metres."""
    if len(frames) < 2:
        return 0.0
    steps = np.linalg.norm(np.diff(xy_m, axis=0), axis=1)
    return float(steps[np.diff(frames) <= max_gap].sum())


def top_speed_m_s(frames: np.ndarray, xy_m: np.ndarray, window: int, fps: float) -> float:
    """Largest displacement over `window` frames (within runs of consecutive frames) per second; NaN if too short."""
    best = np.nan
    for run in _runs(frames, 1):
        seg = xy_m[run]
        if len(seg) > window:
            speed = np.linalg.norm(seg[window:] - seg[:-window], axis=1) * fps / window
            best = np.nanmax([best, speed.max()])
    return float(best)


def jitter_m(frames: np.ndarray, xy_m: np.ndarray) -> np.ndarray:
    """Norms of the second differences of positions over three consecutive frames, metres ((M,) array)."""
    if len(frames) < 3:
        return np.zeros(0)
    consecutive = (frames[1:-1] - frames[:-2] == 1) & (frames[2:] - frames[1:-1] == 1)
    second = xy_m[2:] - 2 * xy_m[1:-1] + xy_m[:-2]
    return np.linalg.norm(second[consecutive], axis=1)


def track_analytics(frames, track_ids, xy_m, config: AnalyticsConfig = AnalyticsConfig()) -> dict[int, dict]:
    """Per track: frames seen, distance covered (m), top speed (m/s), jitter RMS (m).

    Args:
        frames: (N,) frame indices; track_ids: (N,) ids (-1 unknown); xy_m: (N, 2) metres (NaN = no position).

    Returns:
        id -> {"frames", "distance_m", "top_speed_m_s", "jitter_rms_m", "raw_distance_m"}.
    """
    out = {}
    for tid, (f, xy) in tracks(frames, track_ids, xy_m).items():
        smooth = smooth_track(f, xy, config.smooth_frames)
        jit = jitter_m(f, xy)
        out[tid] = {
            "frames": int(len(f)),
            "distance_m": track_distance_m(f, smooth, config.max_gap_frames),
            "raw_distance_m": track_distance_m(f, xy, config.max_gap_frames),
            "top_speed_m_s": top_speed_m_s(f, smooth, config.speed_frames, config.fps),
            "jitter_rms_m": float(np.sqrt(np.mean(jit ** 2))) if len(jit) else float("nan"),
        }
    return out


def analytics_summary(per_track: dict[int, dict]) -> dict:
    """Totals over tracks: tracks, total distance, median / max top speed, median jitter (NaN-safe, JSON-ready)."""
    if not per_track:
        return {"tracks": 0}
    dist = np.array([v["distance_m"] for v in per_track.values()])
    speed = np.array([v["top_speed_m_s"] for v in per_track.values()])
    jitter = np.array([v["jitter_rms_m"] for v in per_track.values()])

    def num(x):
        return None if not np.isfinite(x) else round(float(x), 4)

    return {
        "tracks": len(per_track),
        "total_distance_m": num(dist.sum()),
        "median_top_speed_m_s": num(np.nanmedian(speed)) if np.isfinite(speed).any() else None,
        "max_top_speed_m_s": num(np.nanmax(speed)) if np.isfinite(speed).any() else None,
        "median_jitter_rms_m": num(np.nanmedian(jitter)) if np.isfinite(jitter).any() else None,
    }


def all_jitter_m(frames, track_ids, xy_m) -> np.ndarray:
    """Second-difference norms (metres) of every track, concatenated."""
    parts = [jitter_m(f, xy) for f, xy in tracks(frames, track_ids, xy_m).values()]
    return np.concatenate(parts) if parts else np.zeros(0)


def error_stats(errors_m: np.ndarray) -> dict:
    """Median, 95th percentile, mean and count of position errors (metres, NaN dropped)."""
    e = np.asarray(errors_m, dtype=float)
    e = e[np.isfinite(e)]
    if not len(e):
        return {"count": 0, "median_m": None, "p95_m": None, "mean_m": None}
    return {"count": int(len(e)), "median_m": round(float(np.median(e)), 4),
            "p95_m": round(float(np.percentile(e, 95)), 4), "mean_m": round(float(e.mean()), 4)}
