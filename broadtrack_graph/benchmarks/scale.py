"""``broadtrack-graph bench scale``: track-many on Ray, measured.

Parts (``--parts``, all by default):

speedup   four rendered synthetic clips (``--frames`` at ``--width`` x ``--height``, reused from
          ``--out/clips`` when there), tracked online by track-many on a local Ray instance with 1
          and with 2 workers, each unit on its one CPU (no prefetch thread in either run): wall
          time of the job (Ray start excluded, given apart), speed-up, and whether every camera
          file is byte-identical between the two runs. For reference, the 1-worker job once more
          as track-many runs it by default on this machine: its units decode their frames in a
          background thread on the core the single worker leaves idle.
chunked   one long synthetic detections file (``--long-frames``), batch mode: the one-process
          two-pass run (``track --mode batch``: chained chunks), the staged run (windows of
          ``--chunk-frames``) in one process and on 2 Ray workers: times and the largest
          pan / tilt (degrees) and focal-point position (metres) differences between them.
resume    the speed-up job's command run as a subprocess on 1 worker and killed (SIGKILL of its
          process group) once half the clips are done; run again: units not redone, every clip
          complete with each frame once, cameras identical to the uninterrupted run.
cluster   a two-node Ray cluster started here (``ray start --head --node-ip-address 127.0.0.1
          --port P --num-cpus 1`` and ``ray start --address 127.0.0.1:P --num-cpus 1``, own temp
          folder), the speed-up manifest through ``--address``, cameras compared with the local
          run; the cluster's processes (found by that temp folder) are stopped by their ids.
memory    one ``--memory-frames`` clip (synthetic detections file) tracked online as one unit on
          a Ray worker: the worker's resident memory sampled every 2 s over the run.

Timings on a shared machine are upper bounds; the report carries the load average before
each part.
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from broadtrack_graph.io.run_folder import RunFolder

HELP = "track-many on Ray: 2 workers vs 1, chunked batch vs one process, kill and resume, two-node cluster, memory"
PARTS = ("speedup", "chunked", "resume", "cluster", "memory")

log = logging.getLogger(__name__)


def add_arguments(parser) -> None:
    parser.add_argument("--parts", nargs="+", choices=PARTS, default=list(PARTS), help="parts to run (default all)")
    parser.add_argument("--clips", type=int, default=4, help="rendered clips of the speed-up part (default 4)")
    parser.add_argument("--frames", type=int, default=120, help="frames per rendered clip (default 120)")
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=540)
    parser.add_argument("--long-frames", type=int, default=1200, help="frames of the chunked clip (default 1200)")
    parser.add_argument("--chunk-frames", type=int, default=300, help="window size of the chunked part (default 300)")
    parser.add_argument("--overlap", type=int, default=50, help="window overlap (default 50)")
    parser.add_argument("--memory-frames", type=int, default=20000, help="frames of the memory part (default 20000)")
    parser.add_argument("--port", type=int, default=6391, help="GCS port of the loopback cluster (default 6391)")
    parser.add_argument("--out", type=Path, default=Path("bench-scale"), help="work folder (default ./bench-scale)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


def run(args) -> dict:
    from broadtrack_graph.actions.ray_engine import import_ray

    import_ray(loopback=True)  # first import of ray in this process: local instances bind to 127.0.0.1
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    report: dict = {"cores": os.cpu_count(), "parts": {}}
    manifest = None
    if {"speedup", "resume", "cluster"} & set(args.parts):
        manifest = _clips_manifest(args, out)
    for part in args.parts:
        started = time.perf_counter()
        load = os.getloadavg()
        figures = PART_FUNCTIONS[part](args, out, manifest)
        report["parts"][part] = {"load_average_before": [round(v, 2) for v in load],
                                 "part_wall_s": round(time.perf_counter() - started, 2), **figures}
    return report


# ---------------------------------------------------------------------------------------------- parts


def part_speedup(args, out: Path, manifest: Path) -> dict:
    figures = {}
    for workers in (1, 2):
        figures[f"workers_{workers}"] = _ray_job(manifest, out / f"speedup-w{workers}", workers, None, args,
                                                 prefetch=False)
    w1, w2 = figures["workers_1"]["job_wall_s"], figures["workers_2"]["job_wall_s"]
    figures["speedup"] = round(w1 / w2, 3) if w2 else None
    figures["camera_files"] = compare_camera_files(out / "speedup-w1", out / "speedup-w2")
    # The default 1-worker job: its prefetch thread decodes on the core the worker leaves idle.
    reference = _ray_job(manifest, out / "speedup-w1-prefetch", 1, None, args)
    figures["workers_1_with_prefetch_thread"] = reference
    figures["speedup_vs_1_worker_with_prefetch_thread"] = round(reference["job_wall_s"] / w2, 3) if w2 else None
    return figures


def part_chunked(args, out: Path, manifest) -> dict:
    from broadtrack_graph.actions.parallel import SerialEngine
    from broadtrack_graph.actions.ray_engine import RayEngine
    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.actions.track_many import ManyOptions, track_many
    from broadtrack_graph.io.manifest import ClipSpec
    from broadtrack_graph.io.run_folder import read_track
    from broadtrack_graph.track.config import TrackingConfig

    path = _detections(out, args.long_frames, seed=5)
    config = TrackingConfig(mode="batch")
    folder = out / "chunked"
    shutil.rmtree(folder, ignore_errors=True)
    started = time.perf_counter()
    track_input(None, folder / "one-process", config, detections_path=path, progress=not args.no_progress)
    one_s = time.perf_counter() - started
    options = ManyOptions(args.chunk_frames, args.overlap, retries=0, progress=not args.no_progress)
    clip = [ClipSpec("long", detections=path)]
    started = time.perf_counter()
    serial = track_many(clip, folder / "staged-serial", config, options, SerialEngine())
    serial_s = time.perf_counter() - started
    with RayEngine(workers=2, retries=0) as engine:
        ray = track_many(clip, folder / "staged-ray2", config, options, engine)
    tracks = {name: read_track(folder / name if name == "one-process" else folder / name / "long").records
              for name in ("one-process", "staged-serial", "staged-ray2")}
    return {
        "frames": args.long_frames, "chunk_frames": args.chunk_frames, "overlap": args.overlap,
        "units": len(serial.ran), "failed": {**serial.failed, **ray.failed},
        "one_process_batch_s": round(one_s, 2), "staged_serial_s": round(serial_s, 2),
        "staged_ray_2_workers_job_s": ray.wall_s,
        "speedup_ray2_vs_staged_serial": round(serial_s / ray.wall_s, 3) if ray.wall_s else None,
        "ray2_vs_staged_serial": max_differences(tracks["staged-ray2"], tracks["staged-serial"]),
        "ray2_vs_one_process_batch": max_differences(tracks["staged-ray2"], tracks["one-process"]),
        "stage_seconds": _stage_seconds(ray.results),
    }


def part_resume(args, out: Path, manifest: Path) -> dict:
    folder = out / "resume"
    shutil.rmtree(folder, ignore_errors=True)
    command = _cli(["track-many", "--manifest", str(manifest), "--out", str(folder), "--workers", "1", "--no-progress"])
    units = folder / "_units"
    total = sum(1 for line in manifest.read_text().splitlines() if line.strip())
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    killed_at = None
    while process.poll() is None:
        done = len(list(units.glob("*.done"))) if units.is_dir() else 0
        if done >= total // 2:
            os.killpg(process.pid, signal.SIGKILL)  # the driver and the Ray processes it started
            killed_at = done
            break
        time.sleep(0.5)
    process.wait()
    before = sorted(p.name for p in units.glob("*.done"))
    stale = sorted(p.name for p in folder.glob(".*.tmp-*"))
    rerun = subprocess.run(command, capture_output=True, text=True)
    report = json.loads((folder / "track_many.json").read_text())
    counts = {}
    for clip in sorted(p.name for p in folder.iterdir() if p.is_dir() and not p.name.startswith(("_", "."))):
        indices = [json.loads(line)["frame"] for line in RunFolder(folder / clip).track_path.read_text().splitlines()
                   if line.strip()]
        counts[clip] = {"frames": len(indices), "unique": len(set(indices))}
    return {
        "units": total, "done_when_killed": killed_at, "done_markers_after_kill": len(before),
        "temp_folders_left_by_kill": len(stale), "rerun_exit": rerun.returncode,
        "rerun_ran": len(report["ran"]), "rerun_skipped": len(report["skipped"]),
        "redone_after_kill": sorted(set(report["ran"]) & {name[:-5] for name in before}),
        "frames_per_clip": counts,
        "camera_files_vs_uninterrupted": compare_camera_files(folder, out / "speedup-w2")
        if (out / "speedup-w2").is_dir() else None,
    }


def part_cluster(args, out: Path, manifest: Path) -> dict:
    temp = Path(f"/tmp/bt-ray-{os.getpid()}")  # short: Ray's socket paths must stay under 108 characters
    # Token authentication (Ray >= 2.5x) on every node and the driver: the head makes the token
    # (~/.ray/auth_token) and the worker node and the job must present it.
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0", "RAY_AUTH_MODE": "token"}
    env.pop("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", None)  # a second node needs cluster mode on
    ray_bin = str(Path(sys.executable).with_name("ray"))
    address = f"127.0.0.1:{args.port}"
    figures: dict = {"address": address}
    try:
        head = subprocess.run([ray_bin, "start", "--head", "--node-ip-address", "127.0.0.1", "--port", str(args.port),
                               "--num-cpus", "1", "--include-dashboard", "false", "--temp-dir", str(temp),
                               "--disable-usage-stats"], capture_output=True, text=True, env=env, timeout=300)
        worker = subprocess.run([ray_bin, "start", "--address", address, "--num-cpus", "1"],
                                capture_output=True, text=True, env=env, timeout=300)
        figures["ray_start_exit"] = [head.returncode, worker.returncode]
        if head.returncode or worker.returncode:
            figures["error"] = [line for line in (worker.stderr + head.stderr).splitlines() if "Error" in line][-1:]
            return figures
        folder = out / "cluster"
        shutil.rmtree(folder, ignore_errors=True)
        started = time.perf_counter()
        job = subprocess.run(_cli(["track-many", "--manifest", str(manifest), "--out", str(folder), "--address",
                                   address, "--no-progress"]), capture_output=True, text=True, env=env)
        figures["job_exit"] = job.returncode
        figures["job_wall_s_with_connect"] = round(time.perf_counter() - started, 2)
        if job.returncode:
            figures["job_error"] = job.stderr.strip().splitlines()[-3:]
        report = json.loads((folder / "track_many.json").read_text())
        figures.update(job_wall_s=report["wall_s"], workers=report["workers"], ran=len(report["ran"]),
                       hosts_pids=sorted({(r.get("host"), r.get("pid")) for r in report["results"].values()}),
                       node_addresses=_node_addresses(temp))
        figures["camera_files_vs_local"] = compare_camera_files(folder, out / "speedup-w2")
    finally:
        figures["stopped_processes"] = stop_cluster(temp)
    return figures


def part_memory(args, out: Path, manifest) -> dict:
    from broadtrack_graph.actions.ray_engine import RayEngine
    from broadtrack_graph.actions.track_many import ManyOptions, track_many
    from broadtrack_graph.io.manifest import ClipSpec
    from broadtrack_graph.track.config import TrackingConfig

    path = _detections(out, args.memory_frames, seed=7)
    folder = out / "memory"
    shutil.rmtree(folder, ignore_errors=True)
    with RayEngine(workers=1, retries=0) as engine:
        report = track_many([ClipSpec("long", detections=path)], folder, TrackingConfig(mode="online"),
                            ManyOptions(retries=0, progress=not args.no_progress), engine)
    result = report.results.get("long.track", {})
    return {"frames": args.memory_frames, "failed": report.failed, **rss_profile(result)}


PART_FUNCTIONS = {"speedup": part_speedup, "chunked": part_chunked, "resume": part_resume, "cluster": part_cluster,
                  "memory": part_memory}


# ---------------------------------------------------------------------------------------------- helpers


def rss_profile(result: dict) -> dict:
    """Resident memory of a unit's worker: at 10 %, 50 % and the end of its run, and the peak (MB)."""
    samples = result.get("rss_mb") or []
    if not samples:
        return {"rss_mb": None}
    seconds = samples[-1][0] or 1.0

    def at(share):
        return min(samples, key=lambda s: abs(s[0] - share * seconds))[1]

    return {"seconds": result.get("seconds"), "fps": round(result.get("frames", 0) / max(seconds, 1e-9), 2),
            "rss_mb_at_10pct": at(0.1), "rss_mb_at_50pct": at(0.5), "rss_mb_at_end": samples[-1][1],
            "rss_mb_peak": max(s[1] for s in samples), "samples": len(samples)}


def compare_camera_files(a: Path, b: Path) -> dict:
    """Byte comparison of every clip's cameras/*.json between two job folders."""
    same = different = missing = 0
    for clip in sorted(p.name for p in Path(a).iterdir() if RunFolder(p).camera_dir.is_dir()):
        for file in sorted(RunFolder(Path(a) / clip).camera_dir.glob("*.json")):
            other = RunFolder(Path(b) / clip).camera_dir / file.name
            if not other.is_file():
                missing += 1
            elif other.read_bytes() == file.read_bytes():
                same += 1
            else:
                different += 1
    return {"identical": same, "different": different, "missing": missing}


def max_differences(records_a, records_b) -> dict:
    """Largest |pan|, |tilt| (degrees) and focal-point position (metres) differences over frames both have."""
    b = {r.frame_index: r.camera for r in records_b if r.camera is not None}
    pan, tilt, position, frames = [0.0], [0.0], [0.0], 0
    for record in records_a:
        other = b.get(record.frame_index)
        if record.camera is None or other is None:
            continue
        frames += 1
        pan.append(abs((record.camera.pan_deg - other.pan_deg + 180.0) % 360.0 - 180.0))
        tilt.append(abs(record.camera.tilt_deg - other.tilt_deg))
        position.append(float(np.linalg.norm(np.asarray(record.camera.position_m) - np.asarray(other.position_m))))
    return {"frames_compared": frames, "max_pan_deg": float(max(pan)), "max_tilt_deg": float(max(tilt)),
            "max_position_m": float(max(position)), "mean_pan_deg": float(np.mean(pan[1:])) if frames else None}


def stop_cluster(temp: Path) -> list[int]:
    """Stop the processes of the cluster whose temp folder is ``temp`` (found by it), by their ids.

    ``ray stop`` would stop every Ray process on the machine, other users' included.
    """
    mine = _processes_with(str(temp))
    for pid in mine:
        _signal(pid, signal.SIGTERM)
    deadline = time.time() + 20
    while time.time() < deadline and any(_alive(pid) for pid in mine):
        time.sleep(0.5)
    for pid in mine:
        if _alive(pid):
            _signal(pid, signal.SIGKILL)
    shutil.rmtree(temp, ignore_errors=True)
    return mine


def _processes_with(text: str) -> list[int]:
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and int(entry.name) != os.getpid():
            try:
                if text in (entry / "cmdline").read_bytes().decode(errors="replace"):
                    pids.append(int(entry.name))
            except OSError:
                continue
    return sorted(pids)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except OSError:
        return False
    return True


def _signal(pid: int, sig) -> None:
    try:
        os.kill(pid, sig)
    except OSError:
        pass


def _node_addresses(temp: Path) -> list[str]:
    """--node-ip-address of the cluster's raylets (from their command lines)."""
    found = set()
    for pid in _processes_with(str(temp)):
        try:
            words = Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace").split("\0")
        except OSError:
            continue
        for word in words:
            if word.startswith("--node_ip_address=") or word.startswith("--node-ip-address="):
                found.add(word.split("=", 1)[1])
    return sorted(found)


def _ray_job(manifest: Path, folder: Path, workers: int, address: str | None, args,
             prefetch: bool | None = None) -> dict:
    from broadtrack_graph.actions.ray_engine import RayEngine
    from broadtrack_graph.actions.track_many import ManyOptions, track_many
    from broadtrack_graph.io.manifest import read_manifest
    from broadtrack_graph.track.config import TrackingConfig

    shutil.rmtree(folder, ignore_errors=True)
    started = time.perf_counter()
    with RayEngine(workers, address, retries=0, prefetch=prefetch) as engine:
        start_s = time.perf_counter() - started
        report = track_many(read_manifest(manifest), folder, TrackingConfig(mode="online"),
                            ManyOptions(retries=0, progress=not args.no_progress), engine)
    seconds = [r.get("seconds", 0.0) for r in report.results.values()]
    return {"ray_start_s": round(start_s, 2), "job_wall_s": report.wall_s, "units": len(report.ran),
            "failed": report.failed, "unit_seconds_sum": round(sum(seconds), 2),
            "clips": report.clips}


def _clips_manifest(args, out: Path) -> Path:
    from broadtrack_graph.benchmarks.clips import ensure_clip
    from broadtrack_graph.io.manifest import write_manifest

    entries = []
    for seed in range(args.clips):
        clip, _ = ensure_clip(out / "clips", "main", args.frames, args.width, args.height, seed, not args.no_progress)
        entries.append({"input": str(clip), "name": f"clip{seed}"})
    return write_manifest(out / "clips.jsonl", entries)


def _detections(out: Path, frames: int, seed: int) -> Path:
    from broadtrack_graph.synth.detections_file import write_synthetic_detections

    path = out / "detections" / f"main-s{seed}-{frames}f-1280x720.jsonl"
    if not path.is_file():
        path.parent.mkdir(parents=True, exist_ok=True)
        write_synthetic_detections(path, frames, seed=seed)
    return path


def _stage_seconds(results: dict) -> dict:
    totals: dict = {}
    for unit, result in results.items():
        kind = unit.rsplit(".", 1)[-1].split("-")[0]
        totals[kind] = round(totals.get(kind, 0.0) + float(result.get("seconds") or 0.0), 2)
    return totals


def _cli(arguments: list[str]) -> list[str]:
    return [sys.executable, "-m", "broadtrack_graph.cli", *arguments]
