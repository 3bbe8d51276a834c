"""Figures of the endurance run: per-block time, memory and ground-truth scores, flatness trends,
the per-frame CSV and the plot.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from broadtrack_graph.benchmarks.endurance_clip import endurance_frame_id, pingpong_index
from broadtrack_graph.benchmarks.process_stats import FrameClock, peak_rss_mb


def stats_ms(values) -> dict:
    """Median / p90 / max of per-frame milliseconds (values: (N,) ms), rounded; None entries when empty."""
    values = np.asarray(values, float)
    if not len(values):
        return {"median": None, "p90": None, "mean": None, "max": None}
    return {"median": round(float(np.median(values)), 3), "p90": round(float(np.percentile(values, 90)), 3),
            "mean": round(float(np.mean(values)), 3), "max": round(float(np.max(values)), 3)}


def slope_per_1000(x_frames, y) -> float | None:
    """Least-squares slope of y against the frame index, per 1000 frames (None with < 2 points)."""
    x, y = np.asarray(x_frames, float), np.asarray(y, float)
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 2 or np.ptp(x[keep]) == 0:
        return None
    return float(np.polyfit(x[keep], y[keep], 1)[0] * 1000.0)


def rss_at(samples: list[tuple[int, float]], frames_done: int) -> float | None:
    """The last RSS sample taken at or before ``frames_done`` frames."""
    value = None
    for count, mb in samples:
        if count <= frames_done:
            value = mb
    return value


def ground_truth_scores(records, segment: Path, unique_frames: int, width_px: int, height_px: int,
                        every: int) -> dict[int, dict]:
    """JaC@5, mean reprojection error and camera errors of every ``every``-th frame against the ground truth.

    Frames whose segment frame has no line annotation are left out (the metric cannot
    score them). A frame without a camera scores JaC 0 and no error (``camera`` False).

    Returns:
        frame index -> {"camera": bool, "jac_5": float, "mre_px": float or None,
        "pan_error_deg": float or None, "focal_error_rel": float or None}.
    """
    from broadtrack_graph.geometry.template import TemplateSampling
    from broadtrack_graph.io.annotations import read_annotations
    from broadtrack_graph.io.cameras import read_camera_file
    from broadtrack_graph.metrics.soccernet import evaluate_frame

    if every <= 0:
        return {}
    annotations = read_annotations(segment).frames
    sampling = TemplateSampling()
    truth_cache: dict[str, object] = {}
    out: dict[int, dict] = {}
    for record in records:
        k = record.frame_index
        if k % every:
            continue
        segment_id = endurance_frame_id(pingpong_index(k, unique_frames))
        lines = annotations.get(segment_id)
        if not lines:
            continue
        camera = record.camera
        if camera is None:
            out[k] = {"camera": False, "jac_5": 0.0, "mre_px": None, "pan_error_deg": None, "focal_error_rel": None}
            continue
        score = evaluate_frame(lines, camera, width_px, height_px, (5.0,), sampling)
        distances = score.all_distances(5.0)
        if segment_id not in truth_cache:
            truth_cache[segment_id] = read_camera_file(segment / "cameras" / f"camera_{segment_id}.json", width_px, height_px)
        truth = truth_cache[segment_id]
        pan_error = math.degrees(math.remainder(camera.pan_rad - truth.pan_rad, 2 * math.pi))
        out[k] = {"camera": True, "jac_5": float(score.jac[5.0]),
                  "mre_px": float(np.mean(distances)) if len(distances) else None,
                  "pan_error_deg": float(pan_error), "focal_error_rel": float(camera.focal_px / truth.focal_px - 1.0)}
    return out


def block_figures(clock: FrameClock, records, scores: dict[int, dict], block: int) -> list[dict]:
    """Per block of ``block`` frames (by position in the run): time, RSS, statuses and ground-truth figures."""
    frames = len(clock.process_ms)
    by_index = {r.frame_index: r for r in records}
    out = []
    for start in range(0, frames, block):
        end = min(start + block, frames)
        block_records = [by_index[k] for k in range(start, end) if k in by_index]
        statuses: dict[str, int] = {}
        for record in block_records:
            if record.status != "tracked":
                statuses[record.status] = statuses.get(record.status, 0) + 1
        scored = [scores[k] for k in range(start, end) if k in scores]
        with_error = [s for s in scored if s["mre_px"] is not None]
        out.append({
            "first_frame": start, "frames": end - start,
            "ms": stats_ms(clock.process_ms[start:end]),
            "cpu_ms_median": round(float(np.median(clock.cpu_ms[start:end])), 3),
            "interval_ms_median": round(float(np.median(clock.interval_ms[start:end])), 3),
            "rss_mb": None if (value := rss_at(clock.rss, end)) is None else round(value, 1),
            "reinitialisations": sum(int(r.reinitialised) for r in block_records),
            "failed": statuses.get("failed", 0),
            "frames_without_camera": sum(int(r.camera is None) for r in block_records),
            "statuses_other_than_tracked": statuses,
            "scored_frames": len(scored),
            "jac_5": round(float(np.mean([s["jac_5"] for s in scored])), 4) if scored else None,
            "mre_px": round(float(np.mean([s["mre_px"] for s in with_error])), 3) if with_error else None,
            "pan_error_median_abs_deg": round(float(np.median([abs(s["pan_error_deg"]) for s in with_error])), 4)
            if with_error else None,
            "focal_error_median_abs_pct": round(100.0 * float(np.median([abs(s["focal_error_rel"]) for s in with_error])), 3)
            if with_error else None,
        })
    return out


def flatness(blocks: list[dict], clock: FrameClock) -> dict:
    """Last / first block ratios and trends of the per-frame time and of the RSS after the first block.

    The RSS figures use the samples taken while frames were flowing (0 < frames done < all):
    when the last frame is decoded the prefetch thread ends and its malloc arena is handed
    back, which drops the RSS by tens of MB without saying anything about growth. The RSS
    of the last block is the median of its samples (glibc trims arenas now and then, which
    shows as short dips).
    """
    if not blocks:
        return {}
    first, last = blocks[0], blocks[-1]
    total = last["first_frame"] + last["frames"]
    x = [b["first_frame"] + b["frames"] / 2 for b in blocks]
    flowing = [(c, mb) for c, mb in clock.rss if 0 < c < total] or [(c, mb) for c, mb in clock.rss if c > 0]
    rss_first = first["rss_mb"]
    in_last = [mb for c, mb in flowing if c > last["first_frame"]] or [mb for _, mb in flowing[-1:]]
    rss_last = round(float(np.median(in_last)), 1) if in_last else None
    after = [(c, mb) for c, mb in flowing if c >= first["frames"]]

    def ratio(a, b):
        return round(a / b, 3) if a is not None and b else None

    def rounded(value, digits):
        return None if value is None else round(value, digits)

    return {
        "ms_median_first_block": first["ms"]["median"],
        "ms_median_last_block": last["ms"]["median"],
        "ms_ratio_last_to_first": ratio(last["ms"]["median"], first["ms"]["median"]),
        "cpu_ms_ratio_last_to_first": ratio(last["cpu_ms_median"], first["cpu_ms_median"]),
        "ms_p90_ratio_last_to_first": ratio(last["ms"]["p90"], first["ms"]["p90"]),
        "ms_median_trend_per_1000_frames": rounded(slope_per_1000(x, [b["ms"]["median"] for b in blocks]), 4),
        "cpu_ms_median_trend_per_1000_frames": rounded(slope_per_1000(x, [b["cpu_ms_median"] for b in blocks]), 4),
        "rss_mb_end_of_first_block": rss_first,
        "rss_mb_last_block": rss_last,
        "rss_growth_mb_after_first_block": None if rss_first is None or rss_last is None
        else round(rss_last - rss_first, 1),
        "rss_trend_mb_per_1000_frames_after_first_block": rounded(
            slope_per_1000([c for c, _ in after], [mb for _, mb in after]), 3),
        "rss_mb_after_last_frame": None if not clock.rss else round(clock.rss[-1][1], 1),
        "rss_peak_mb": rounded(peak_rss_mb(), 1),
    }


def write_per_frame_csv(path: Path, clock: FrameClock) -> None:
    """frame, process_ms, cpu_ms, interval_ms (one line per frame)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("frame,process_ms,cpu_ms,interval_ms\n")
        for k, (wall, cpu, interval) in enumerate(zip(clock.process_ms, clock.cpu_ms, clock.interval_ms)):
            handle.write(f"{k},{wall:.3f},{cpu:.3f},{interval:.3f}\n")


def plot_blocks(path: Path, blocks: list[dict], clock: FrameClock, title: str) -> None:
    """ms/frame (median, p90, CPU median), RSS and JaC@5 / re-initialisations per block against the frame index."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.array([b["first_frame"] + b["frames"] / 2 for b in blocks], float)
    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    ax = axes[0]
    ax.plot(x, [b["ms"]["median"] for b in blocks], "o-", label="wall, median")
    ax.plot(x, [b["ms"]["p90"] for b in blocks], "s--", label="wall, p90")
    ax.plot(x, [b["cpu_ms_median"] for b in blocks], "^-", label="CPU (main thread), median")
    ax.set_ylabel("ms per frame")
    ax.set_ylim(bottom=0)
    ax.legend(loc="lower left", fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title(title, fontsize=10)
    ax = axes[1]
    if clock.rss:
        ax.plot([c for c, _ in clock.rss], [mb for _, mb in clock.rss], "-", lw=1, label="RSS (every 100 frames)")
    ax.plot(x + np.array([b["frames"] / 2 for b in blocks]), [b["rss_mb"] for b in blocks], "o", label="end of block")
    ax.set_ylabel("RSS (MB)")
    ax.set_ylim(bottom=0)
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[2]
    jac = [np.nan if b["jac_5"] is None else 100.0 * b["jac_5"] for b in blocks]
    ax.plot(x, jac, "o-", color="tab:green", label="JaC@5 (%) of the scored frames")
    ax.set_ylabel("JaC@5 (%)")
    ax.set_ylim(0, 105)
    ax.set_xlabel("frame")
    ax.grid(alpha=0.3)
    twin = ax.twinx()
    twin.bar(x, [b["reinitialisations"] for b in blocks], width=0.4 * (x[1] - x[0]) if len(x) > 1 else 1.0,
             alpha=0.3, color="tab:red", label="re-initialisations")
    twin.set_ylabel("re-initialisations per block")
    lines = ax.get_legend_handles_labels()
    bars = twin.get_legend_handles_labels()
    ax.legend(lines[0] + bars[0], lines[1] + bars[1], loc="lower left", fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
