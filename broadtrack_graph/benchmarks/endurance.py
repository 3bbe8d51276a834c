"""``broadtrack-graph bench endurance``: a long clip tracked online, per-block time and memory, and a killed run.

The product's claim (README, "Modes"): online tracking keeps a flat per-frame cost over a
match, and an interrupted run keeps every frame it wrote. This suite measures both.

The clip. A segment of ``--unique-frames`` frames of a synthetic preset (default ``long``,
1920x1080) is rendered once (:func:`~broadtrack_graph.benchmarks.accuracy.ensure_clip`,
reused from ``--out`` when present) and the ``--frames``-frame clip (default 20,000) is a
folder of numbered images that plays the segment forwards, backwards, forwards...
(``frames/000001.jpg`` ... as symbolic links to the segment's JPEGs; see
:func:`pingpong_index`). The camera path stays continuous (the motion reverses at each end
of the segment) and every frame keeps its exact ground truth: the segment frame it shows.
Rendering costs ~0.2-0.5 s per HD frame here, so 20,000 unique frames would take hours;
with ``--unique-frames`` >= ``--frames`` the clip is rendered in full and played once.
Tracking reads JPEG frames, so its time never includes rendering.

The tracked run. The clip is tracked online with the weight-free detector through the
product's own loop (:class:`~broadtrack_graph.track.frame_loop.TrackingRun` and
:func:`~broadtrack_graph.track.passes.run_loop`, as :func:`~broadtrack_graph.actions.track.track_input`
builds them: frames prefetched and decoded in a background thread). Each call of
``TrackingRun.process`` is timed (wall clock and the main thread's CPU time: on a shared
machine the CPU time is the steadier figure); the process RSS (``VmRSS`` of
``/proc/self/status``) is sampled every 100 frames. Per block of ``--block`` frames
(default 1000): median / p90 / max ms per frame, median CPU ms, median interval between
finished frames (includes waiting for a decoded frame), RSS at the block's end, counts of
re-initialisations and of frames per non-tracked status, and against the ground truth on
every ``--eval-every``-th frame: the SoccerNet JaC@5, MRE (px) and the pan / focal error
of the estimate. Flatness: last-block / first-block median ratios and the linear trend of
the block medians and of the RSS after the first block.

The killed run. ``broadtrack-graph track`` runs on the same clip as a subprocess and is
sent SIGKILL once its ``track.jsonl`` holds ``--kill-fraction`` of the frames (default
0.5; ``--no-kill`` skips this step). Then every ``camera_*.json`` must read
(:func:`~broadtrack_graph.io.cameras.read_camera_file`), ``track.jsonl`` must read with
:func:`~broadtrack_graph.io.run_folder.read_track`, and the two must agree (every record
with a camera has its file, with the same camera; at most one file of the frame in flight
has no line yet); its cameras are compared with the full run's on the same frames (the
same code tracks the same frames identically; ``same_code_as_tracked_run`` says whether the
package sources changed on disk between the two runs, which a shared working tree allows).

Outputs: the JSON report (stdout, ``--json``), a plot (``--plot``, default
``OUT/endurance.png``: ms/frame, RSS and JaC@5 per block against the frame index) and
``OUT/per_frame.csv`` (frame, process_ms, cpu_ms, interval_ms).
"""

from __future__ import annotations

import json
import logging
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from array import array
from pathlib import Path

import cv2
import numpy as np

HELP = ("endurance: track a 20,000-frame clip online (ms/frame and RSS per 1000 frames, JaC@5), "
        "then kill a track run halfway and check that every frame it wrote reads back")

log = logging.getLogger(__name__)

CLIP_INFO = "endurance_clip.json"
"""Marker of an assembled endurance clip folder (segment, frame count): reused when it matches."""

RSS_EVERY_FRAMES = 100
"""The process RSS is sampled every this many frames (and at the end of every block)."""


def add_arguments(parser) -> None:
    from broadtrack_graph.synth.motion import PRESETS

    parser.add_argument("--preset", default="long", choices=sorted(PRESETS), help="synthetic preset (default long)")
    parser.add_argument("--frames", type=int, default=20000, help="frames of the tracked clip (default 20000)")
    parser.add_argument("--unique-frames", type=int, default=1000,
                        help="frames actually rendered; the clip plays them forwards and backwards until --frames "
                             "(default 1000; >= --frames renders the whole clip)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--seed", type=int, default=0, help="clip seed (default 0)")
    parser.add_argument("--block", type=int, default=1000, help="frames per reported block (default 1000)")
    parser.add_argument("--eval-every", type=int, default=10,
                        help="score every N-th frame against the ground truth (default 10; 0: no scoring)")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--no-kill", action="store_true", help="skip the killed-run check")
    parser.add_argument("--kill-fraction", type=float, default=0.5,
                        help="SIGKILL the track subprocess once this share of the frames is written (default 0.5)")
    parser.add_argument("--out", type=Path, default=Path("bench-endurance"),
                        help="folder for clips/, runs/ and per_frame.csv (default ./bench-endurance); a rendered "
                             "segment found there is reused")
    parser.add_argument("--plot", type=Path, default=None, help="plot file (default OUT/endurance.png)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


# --------------------------------------------------------------------------- the clip


def pingpong_index(frame_index: int, unique_frames: int) -> int:
    """Index in the rendered segment of a frame of the endurance clip (forwards, backwards, ...).

    Frames 0..U-1 show the segment, U..2U-3 show it backwards (U-2 down to 1), then 2U-2
    starts again at 0: the period is 2U-2, and consecutive frames are always neighbours.

    Args:
        frame_index: 0-based frame of the endurance clip.
        unique_frames: U, frames of the segment (>= 1).
    """
    if unique_frames < 1:
        raise ValueError(f"unique_frames must be >= 1, got {unique_frames}")
    if unique_frames == 1:
        return 0
    period = 2 * unique_frames - 2
    phase = int(frame_index) % period
    return phase if phase < unique_frames else period - phase


def endurance_frame_id(frame_index: int) -> str:
    """Image stem of a frame of the endurance clip: 0 -> "000001" (SoccerNet's 1-based, 6 digits)."""
    return f"{frame_index + 1:06d}"


def ensure_endurance_clip(segment: Path, folder: Path, frames: int, unique_frames: int) -> tuple[Path, bool]:
    """The ``frames``-frame image folder playing ``segment``'s img1/ back and forth (built or reused).

    Returns:
        (folder, True when it was built now).
    """
    wanted = {"segment": str(segment.resolve()), "frames": int(frames), "unique_frames": int(unique_frames)}
    info_path = folder / CLIP_INFO
    if info_path.is_file():
        try:
            if json.loads(info_path.read_text(encoding="utf-8")) == wanted:
                return folder, False
        except (OSError, json.JSONDecodeError):
            pass
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    images = segment.resolve() / "img1"
    for k in range(frames):
        source = images / f"{endurance_frame_id(pingpong_index(k, unique_frames))}.jpg"
        os.symlink(source, folder / f"{endurance_frame_id(k)}.jpg")
    info_path.write_text(json.dumps(wanted), encoding="utf-8")
    return folder, True


# --------------------------------------------------------------------------- measuring


def rss_mb() -> float | None:
    """Resident set size of this process in MB (VmRSS of /proc/self/status; None where there is none)."""
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def peak_rss_mb() -> float | None:
    """Peak resident set size of this process in MB (ru_maxrss, kilobytes on Linux)."""
    try:
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    except (ImportError, OSError):
        return None


class FrameClock:
    """Times every ``TrackingRun.process`` call and samples the RSS (wraps the run's method).

    Attributes (arrays, one entry per processed frame, in order):
        process_ms: wall time of the call; cpu_ms: CPU time of the calling thread during it;
        interval_ms: wall time since the previous call ended (the first: since wrapping).
        rss: (frames processed, MB) samples, every ``rss_every`` frames, at the end of every
            ``block`` frames and (:meth:`sample_rss`) when the caller asks.
    """

    def __init__(self, run, rss_every: int = RSS_EVERY_FRAMES, block: int | None = None) -> None:
        # array('d'): 8 bytes a value, so the bookkeeping adds < 0.1 MB per 1000 frames to the RSS it measures.
        self.process_ms = array("d")
        self.cpu_ms = array("d")
        self.interval_ms = array("d")
        self.rss: list[tuple[int, float]] = []
        self.rss_every = max(1, int(rss_every))
        self.block = None if block is None else max(1, int(block))
        self._inner = run.process
        self._last_end = time.perf_counter()
        first = rss_mb()
        if first is not None:
            self.rss.append((0, first))
        run.process = self  # run_loop calls run.process(frame)

    def __call__(self, frame) -> None:
        wall0, cpu0 = time.perf_counter(), time.thread_time()
        try:
            self._inner(frame)
        finally:
            wall1, cpu1 = time.perf_counter(), time.thread_time()
            self.process_ms.append(1000.0 * (wall1 - wall0))
            self.cpu_ms.append(1000.0 * (cpu1 - cpu0))
            self.interval_ms.append(1000.0 * (wall1 - self._last_end))
            self._last_end = wall1
            count = len(self.process_ms)
            if count % self.rss_every == 0 or (self.block is not None and count % self.block == 0):
                self.sample_rss()

    def sample_rss(self) -> None:
        """Record the RSS now, against the number of frames processed so far (once per count)."""
        count = len(self.process_ms)
        value = rss_mb()
        if value is not None and (not self.rss or self.rss[-1][0] != count):
            self.rss.append((count, value))


def track_timed(clip: Path, run_dir: Path, config, progress: bool, block: int | None = None):
    """Track an image folder online as ``track_input`` does, with every frame timed.

    Returns:
        (RunResult, FrameClock).
    """
    from broadtrack_graph.actions.track import DetectorOptions, make_detector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.io.frames import open_frames
    from broadtrack_graph.track.frame_loop import TrackingRun
    from broadtrack_graph.track.inputs import frames_from_source
    from broadtrack_graph.track.passes import run_loop

    pitch = PitchTemplate()
    with open_frames(clip) as source:
        run_info = {"input": str(clip), "detections": None, "detector": "weightfree", "source": source.describe()}
        run = TrackingRun(source.width_px, source.height_px, run_dir, config, make_detector(DetectorOptions("weightfree"),
                          pitch), None, pitch, None, run_info)
        clock = FrameClock(run, block=block)
        run_loop(run, frames_from_source(source), progress, len(source), config.mode)
        clock.sample_rss()  # after the last frame
        return run.finish(), clock


def _stats_ms(values) -> dict:
    values = np.asarray(values, float)
    if not len(values):
        return {"median": None, "p90": None, "mean": None, "max": None}
    return {"median": round(float(np.median(values)), 3), "p90": round(float(np.percentile(values, 90)), 3),
            "mean": round(float(np.mean(values)), 3), "max": round(float(np.max(values)), 3)}


def _slope_per_1000(x_frames, y) -> float | None:
    """Least-squares slope of y against the frame index, per 1000 frames (None with < 2 points)."""
    x, y = np.asarray(x_frames, float), np.asarray(y, float)
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 2 or np.ptp(x[keep]) == 0:
        return None
    return float(np.polyfit(x[keep], y[keep], 1)[0] * 1000.0)


def _rss_at(samples: list[tuple[int, float]], frames_done: int) -> float | None:
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
            "ms": _stats_ms(clock.process_ms[start:end]),
            "cpu_ms_median": round(float(np.median(clock.cpu_ms[start:end])), 3),
            "interval_ms_median": round(float(np.median(clock.interval_ms[start:end])), 3),
            "rss_mb": None if (value := _rss_at(clock.rss, end)) is None else round(value, 1),
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
        "ms_median_trend_per_1000_frames": rounded(_slope_per_1000(x, [b["ms"]["median"] for b in blocks]), 4),
        "cpu_ms_median_trend_per_1000_frames": rounded(_slope_per_1000(x, [b["cpu_ms_median"] for b in blocks]), 4),
        "rss_mb_end_of_first_block": rss_first,
        "rss_mb_last_block": rss_last,
        "rss_growth_mb_after_first_block": None if rss_first is None or rss_last is None
        else round(rss_last - rss_first, 1),
        "rss_trend_mb_per_1000_frames_after_first_block": rounded(
            _slope_per_1000([c for c, _ in after], [mb for _, mb in after]), 3),
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


def source_digest() -> str:
    """SHA-1 (12 hex digits) of the package's and the factors' Python sources as they are on disk now.

    The tracked run imports the code once; the killed run is a new process that imports it
    again minutes later. When the sources changed in between (a shared working tree), the
    two runs are not comparable frame by frame, and the report says so.
    """
    import hashlib

    import broadtrack_graph
    import factors

    digest = hashlib.sha1()
    for package in (broadtrack_graph, factors):
        root = Path(package.__file__).parent
        for path in sorted(root.rglob("*.py")):
            digest.update(str(path.relative_to(root.parent)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:12]


# --------------------------------------------------------------------------- the killed run


def _count_lines(path: Path, state: dict) -> int:
    """Complete lines in a growing file, reading only what was added since the last call."""
    if not path.is_file():
        return state.get("lines", 0)
    with open(path, "rb") as handle:
        handle.seek(state.get("offset", 0))
        data = handle.read()
    state["offset"] = state.get("offset", 0) + len(data)
    state["lines"] = state.get("lines", 0) + data.count(b"\n")
    return state["lines"]


def kill_track_run(clip: Path, run_dir: Path, kill_after_lines: int, timeout_s: float, poll_s: float = 0.02) -> dict:
    """Run ``broadtrack-graph track CLIP --out RUN`` as a subprocess and SIGKILL it after ``kill_after_lines`` lines.

    Returns:
        {"command", "killed" (False when it ended first), "returncode", "lines_when_killed",
         "seconds", "log"}.
    """
    from broadtrack_graph.io.run_folder import RunFolder

    if run_dir.exists():
        shutil.rmtree(run_dir)  # an earlier run's track.jsonl must not be counted
    run_dir.parent.mkdir(parents=True, exist_ok=True)
    log_path = run_dir.parent / f"{run_dir.name}.log"
    command = [sys.executable, "-m", "broadtrack_graph.cli", "track", str(clip), "--out", str(run_dir), "--no-progress"]
    track_path = RunFolder(run_dir).track_path
    state: dict = {}
    started = time.perf_counter()
    killed = False
    with open(log_path, "w", encoding="utf-8") as log_file:
        process = subprocess.Popen(command, stdout=log_file, stderr=subprocess.STDOUT)
        try:
            while process.poll() is None:
                if _count_lines(track_path, state) >= kill_after_lines:
                    process.send_signal(signal.SIGKILL)
                    killed = True
                    break
                if time.perf_counter() - started > timeout_s:
                    log.error("the track subprocess wrote %d lines in %.0f s; killing it", state.get("lines", 0), timeout_s)
                    process.send_signal(signal.SIGKILL)
                    killed = True
                    break
                time.sleep(poll_s)
        finally:
            if process.poll() is None and not killed:
                process.kill()
            process.wait()
    return {"command": " ".join(command), "killed": killed, "returncode": process.returncode,
            "lines_when_killed": state.get("lines", 0), "seconds": round(time.perf_counter() - started, 2),
            "log": str(log_path)}


def check_interrupted_run(run_dir: Path, reference_records=None) -> dict:
    """Is everything a killed run wrote readable, and do its camera files and track lines agree?

    Args:
        run_dir: the run folder.
        reference_records: records of an uninterrupted run of the same clip (optional), to
            compare the cameras of the frames both have.

    Returns:
        A JSON-ready dict: camera files (count, unreadable with their errors), track records,
        skipped lines (a truncated last line), summary state, agreement checks, and
        ``all_readable`` / ``counts_agree`` / ``ok``.
    """
    from broadtrack_graph.errors import InputError
    from broadtrack_graph.io.cameras import read_camera_file
    from broadtrack_graph.io.run_folder import RunFolder, read_track

    out: dict = {"run": str(run_dir)}
    folder = RunFolder(run_dir)
    files = folder.camera_files()
    cameras, unreadable = {}, {}
    for frame_id, path in files.items():
        try:
            cameras[frame_id] = read_camera_file(path)
        except InputError as exc:
            unreadable[frame_id] = str(exc)
    out["camera_files"] = len(files)
    out["camera_files_unreadable"] = len(unreadable)
    out["unreadable_examples"] = dict(list(unreadable.items())[:5])
    try:
        track = read_track(run_dir)
        track_error = None
    except InputError as exc:
        track, track_error = None, str(exc)
    out["track_error"] = track_error
    try:
        summary = folder.read_summary()
        out["summary_readable"] = True
        out["summary_complete"] = bool(summary.get("complete"))
        out["summary_frames_written"] = summary.get("frames_written")
    except InputError as exc:
        out["summary_readable"] = False
        out["summary_error"] = str(exc)
    records = [] if track is None else track.records
    out["track_records"] = len(records)
    out["track_skipped_lines"] = 0 if track is None else track.skipped_lines
    with_camera = {r.frame_id: r for r in records if r.camera is not None}
    out["track_records_with_camera"] = len(with_camera)
    missing_files = sorted(set(with_camera) - set(files))
    extra_files = sorted(set(files) - set(with_camera))
    mismatched = []
    for frame_id, record in with_camera.items():
        camera = cameras.get(frame_id)
        if camera is not None and not np.allclose(camera.to_vector(), record.camera.to_vector(), rtol=1e-9, atol=1e-6):
            mismatched.append(frame_id)
    indices = [r.frame_index for r in records]
    out["records_missing_camera_file"] = len(missing_files)
    out["camera_files_without_record"] = extra_files[:20]  # at most the frame in flight when killed
    out["camera_file_differs_from_record"] = len(mismatched)
    out["frame_indices_contiguous"] = indices == list(range(len(indices)))
    out["all_readable"] = bool(track_error is None and not unreadable and out["summary_readable"]
                               and out["track_skipped_lines"] <= 1)
    out["counts_agree"] = bool(not missing_files and len(extra_files) <= 1 and not mismatched
                               and out["frame_indices_contiguous"])
    if reference_records is not None and records:
        reference = {r.frame_index: r for r in reference_records}
        diffs_pan, diffs_f, compared, differing_status, differing_camera = [], [], 0, 0, 0
        for record in records:
            other = reference.get(record.frame_index)
            if other is None:
                continue
            compared += 1
            differing_status += int(record.status != other.status)
            if (record.camera is None) != (other.camera is None):
                differing_camera += 1
            elif record.camera is not None:
                diffs_pan.append(abs(math.degrees(math.remainder(record.camera.pan_rad - other.camera.pan_rad, 2 * math.pi))))
                diffs_f.append(abs(record.camera.focal_px - other.camera.focal_px))
        out["vs_full_run"] = {
            "frames_compared": compared,
            "frames_with_other_status": differing_status,
            "frames_with_camera_in_one_run_only": differing_camera,
            "max_pan_difference_deg": round(max(diffs_pan), 6) if diffs_pan else None,
            "max_focal_difference_px": round(max(diffs_f), 4) if diffs_f else None,
        }
    out["ok"] = out["all_readable"] and out["counts_agree"]
    return out


# --------------------------------------------------------------------------- the suite


def run(args) -> dict:
    from broadtrack_graph.benchmarks.accuracy import ensure_clip, prepare_suite
    from broadtrack_graph.benchmarks.speed import stage_figures
    from broadtrack_graph.errors import InputError
    from broadtrack_graph.track.config import TrackingConfig

    progress, out = prepare_suite(args)
    if args.unique_frames < 2 or args.block < 1 or not 0.0 < args.kill_fraction < 1.0:
        raise InputError(None, f"--unique-frames must be >= 2, --block >= 1 and --kill-fraction in (0, 1); got "
                               f"{args.unique_frames}, {args.block}, {args.kill_fraction}")
    unique = min(args.unique_frames, args.frames)
    started = time.perf_counter()
    segment, rendered = ensure_clip(out / "clips", args.preset, unique, args.width, args.height, args.seed, progress)
    render_s = round(time.perf_counter() - started, 2) if rendered else None
    clip, _ = ensure_endurance_clip(segment, out / "clips" / f"endurance-{args.frames}f-from-{segment.name}",
                                        args.frames, unique)
    report: dict = {
        "preset": args.preset, "frames": args.frames, "unique_frames": unique, "width_px": args.width,
        "height_px": args.height, "seed": args.seed, "block_frames": args.block, "eval_every": args.eval_every,
        "opencv_threads": cv2.getNumThreads(), "detector": "weightfree", "mode": "online",
        "clip": {"path": str(clip), "segment": str(segment), "segment_rendered_now": rendered, "render_s": render_s,
                 "render_s_per_frame": round(render_s / unique, 3) if render_s else None,
                 "playback": "forwards-backwards" if unique < args.frames else "once"},
    }

    config = TrackingConfig(mode="online")
    run_dir = out / "runs" / "online"
    report["source_digest"] = source_digest()
    cpu0, wall0 = time.process_time(), time.perf_counter()
    result, clock = track_timed(clip, run_dir, config, progress, args.block)
    wall_s, cpu_s = time.perf_counter() - wall0, time.process_time() - cpu0
    summary = result.summary
    frames = int(summary.get("frames_written", 0))
    scores = ground_truth_scores(result.records, segment, unique, args.width, args.height, args.eval_every)
    blocks = block_figures(clock, result.records, scores, args.block)
    scored = list(scores.values())
    with_error = [s for s in scored if s["mre_px"] is not None]
    report["tracking"] = {
        "frames": frames, "wall_s": round(wall_s, 2), "cpu_s_process": round(cpu_s, 2),
        "fps_wall": round(frames / wall_s, 3) if wall_s > 0 else None,
        "ms_per_frame": _stats_ms(clock.process_ms),
        "cpu_ms_median": round(float(np.median(clock.cpu_ms)), 3) if clock.cpu_ms else None,
        "status_counts": summary.get("status_counts"),
        "reinitialisations": summary.get("reinitialisations"),
        "solver_restarts": summary.get("solver_restarts"),
        "tripod": summary.get("tripod"),
        "stages": stage_figures(summary.get("timings_s") or {}, frames, wall_s),
        "scored_frames": len(scored),
        "jac_5": round(float(np.mean([s["jac_5"] for s in scored])), 4) if scored else None,
        "mre_px": round(float(np.mean([s["mre_px"] for s in with_error])), 3) if with_error else None,
        "run": str(run_dir),
    }
    report["flatness"] = flatness(blocks, clock)
    report["blocks"] = blocks
    report["rss_samples_mb"] = [[count, round(mb, 1)] for count, mb in clock.rss]  # [frames done, MB]
    csv_path = out / "per_frame.csv"
    write_per_frame_csv(csv_path, clock)
    plot_path = args.plot or out / "endurance.png"
    plot_blocks(plot_path, blocks, clock, f"bench endurance: {args.preset}, {frames} frames ({unique} rendered), "
                                          f"{args.width}x{args.height}, online, weight-free detector")
    report["files"] = {"plot": str(plot_path), "per_frame_csv": str(csv_path)}

    if args.no_kill:
        report["interrupted"] = None
        return report
    kill_after = max(1, int(round(args.kill_fraction * args.frames)))
    # Generous: 10x the measured time per frame of the full run, plus the start-up.
    timeout_s = 120.0 + 10.0 * kill_after * (wall_s / max(frames, 1))
    killed_dir = out / "runs" / "killed"
    digest = source_digest()
    launched = kill_track_run(clip, killed_dir, kill_after, timeout_s)
    same_code = digest == report["source_digest"] == source_digest()
    if not same_code:
        log.warning("the package sources changed during the benchmark: the killed run is not comparable frame by "
                    "frame with the tracked run")
    report["interrupted"] = {"kill_after_lines": kill_after, **launched, "source_digest": digest,
                             "same_code_as_tracked_run": same_code,
                             **check_interrupted_run(killed_dir, result.records)}
    return report
