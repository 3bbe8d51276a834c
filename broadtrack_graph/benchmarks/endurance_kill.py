"""The killed run of the endurance suite: ``broadtrack-graph track`` as a subprocess, SIGKILLed
part-way, then every file it wrote is read back and checked against the tracked run.
"""

from __future__ import annotations

import logging
import math
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)


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
