"""The benches' rendered clips: each rendered once and reused, tracked with the weight-free detector, and the stage
timings of a run. Used by ``bench accuracy`` and the benches built on its clips (speed, endurance, players, scale,
broadcast).
"""

from __future__ import annotations

import json
import logging
import time
from pathlib import Path

from broadtrack_graph.io.run_folder import RunFolder

log = logging.getLogger(__name__)


def clip_folder_name(preset: str, frames: int, width_px: int, height_px: int, seed: int) -> str:
    """Folder name of a rendered clip: everything that determines its content."""
    return f"{preset}-s{seed}-{frames}f-{width_px}x{height_px}"


def ensure_clip(clips_dir: Path, preset: str, frames: int, width_px: int, height_px: int, seed: int,
                progress: bool = True) -> tuple[Path, bool]:
    """The rendered clip for these settings: reused when a complete one is in ``clips_dir``, else rendered.

    Returns:
        (clip folder, True when it was rendered now).
    """
    from broadtrack_graph.synth.writer import CLIP_FILE, write_synthetic_clip

    folder = clips_dir / clip_folder_name(preset, frames, width_px, height_px, seed)
    info_path = folder / CLIP_FILE
    if info_path.is_file():
        try:
            info = json.loads(info_path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError):
            info = {}
        wanted = {"preset": preset, "seed": seed, "width_px": width_px, "height_px": height_px,
                  "frame_count": frames, "frames_written": frames}
        if all(info.get(k) == v for k, v in wanted.items()) and (folder / "Labels-GameState.json").is_file():
            log.info("reusing clip %s", folder)
            return folder, False
    write_synthetic_clip(folder, preset=preset, frame_count=frames, width_px=width_px, height_px=height_px,
                         seed=seed, progress=progress)
    return folder, True


def _config_matches(run_dir: Path, config) -> bool:
    from dataclasses import asdict

    summary_path = RunFolder(run_dir).summary_path
    if not summary_path.is_file():
        return False
    try:
        summary = json.loads(summary_path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError):
        return False
    stored = (summary.get("run") or {}).get("config")
    return bool(summary.get("complete")) and stored == json.loads(json.dumps(asdict(config)))


def track_clip(clip: Path, run_dir: Path, config, reuse: bool = False, progress: bool = True) -> dict:
    """Track a clip folder into ``run_dir`` (or reuse a finished run of the same configuration).

    A run that raises is a finding, not the end of the benchmark: the exception is
    recorded (``error``) and the frames it wrote before are still scored (the frames it
    never reached count as frames without a camera).

    Returns:
        {"wall_s": seconds of this call's tracking, to 0.1 ms (None when reused; a run of a few frames can take under
         5 ms, which 0.01 s would round to no time), "reused": bool,
         "summary": the run's summary.json ({} when it crashed), "error": None or
         "<exception type>: <first line>", "frames_written": records in track.jsonl}.
    """
    from broadtrack_graph.actions.track import DetectorOptions, track_input

    if reuse and _config_matches(run_dir, config):
        summary = json.loads(RunFolder(run_dir).summary_path.read_text(encoding="utf-8"))
        return {"wall_s": None, "reused": True, "summary": summary, "error": None,
                "frames_written": summary.get("frames_written")}
    started = time.perf_counter()
    try:
        result = track_input(clip, run_dir, config, DetectorOptions("weightfree"), progress=progress)
    except Exception as exc:  # noqa: BLE001 -- a crashing run is reported, the other runs go on
        message = next((line.strip() for line in str(exc).splitlines() if line.strip()), "")
        written = RunFolder(run_dir).count_track_lines()
        log.error("%s: tracking raised %s: %s (after %d frames)", run_dir, type(exc).__name__, message, written)
        return {"wall_s": round(time.perf_counter() - started, 4), "reused": False, "summary": {},
                "error": f"{type(exc).__name__}: {message}", "frames_written": written}
    return {"wall_s": round(time.perf_counter() - started, 4), "reused": False, "summary": result.summary,
            "error": None, "frames_written": result.summary.get("frames_written")}


def stage_timings(summary: dict) -> dict:
    """Per-stage seconds of a run (``timings_s``); for a batch run, those of its first pass."""
    timings = summary.get("timings_s")
    pass1 = summary.get("pass1")
    if timings is None and pass1 and RunFolder(pass1).has_summary():
        try:
            timings = json.loads(RunFolder(pass1).summary_path.read_text(encoding="utf-8")).get("timings_s")
        except (OSError, json.JSONDecodeError):
            timings = None
    return dict(timings or {})
