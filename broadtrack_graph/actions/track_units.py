"""The units of work of ``track-many`` and the function a worker runs for one: :func:`run_unit`.

A unit is plain data (:class:`Unit`, picklable, JSON-ready) naming its clip, its kind and
everything the worker needs; it reads its inputs from files and writes its outputs into a
temporary folder that is renamed into place, then records itself as done
(``OUT/_units/<id>.done``, JSON with the digest of its inputs and options). Kinds:

    track   a whole clip in its mode (online, fixed-lag, or the two-pass batch run) -> OUT/<clip>/
    pass1   the online first pass over one window of a long clip      -> OUT/_work/<clip>/pass1-NNN/
    tripod  one tripod fitted to the whole first pass (the reduce)     -> OUT/_work/<clip>/tripod/
    refine  batch refinement of one window with that tripod            -> OUT/_work/<clip>/refine-NNN/
    stitch  each window's own frames into the clip's run folder       -> OUT/<clip>/

Paths in a unit are absolute, so that a worker on another node of a cluster finds them on a
shared file system.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import threading
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from broadtrack_graph.io.jsonfile import write_json_atomic

UNITS_DIR = "_units"
WORK_DIR = "_work"
RSS_SAMPLE_S = 2.0  # seconds between samples of a worker's resident memory


@dataclass(frozen=True)
class Unit:
    """One unit of work.

    id: unique in the job, also the done-marker's name ("<clip>.pass1-003").
    clip: the clip's name; kind: track | pass1 | tripod | refine | stitch.
    stage: units of stage n only start after every unit of stage n - 1 finished.
    frames: frames the unit processes (the progress bar's weight).
    out: the folder the unit produces (absolute).
    spec: what the worker needs (JSON-ready: clip fields, tracking config, chunk, input folders).
    depends: ids of units whose outputs this one reads.
    """

    id: str
    clip: str
    kind: str
    stage: int
    frames: int
    out: str
    spec: dict = field(default_factory=dict)
    depends: tuple[str, ...] = ()

    def digest(self) -> str:
        """SHA-256 of the unit's spec, its output folder and the size and time of its input files."""
        stamp = {}
        for key in ("input", "detections", "tripod"):
            path = (self.spec.get("clip") or {}).get(key)
            if path and os.path.exists(path):
                info = os.stat(path)
                stamp[key] = [info.st_size, int(info.st_mtime)]
        text = json.dumps({"kind": self.kind, "out": self.out, "spec": self.spec, "inputs": stamp}, sort_keys=True,
                          default=str)
        return hashlib.sha256(text.encode()).hexdigest()


def done_path(out_root: Path, unit: Unit) -> Path:
    return Path(out_root) / UNITS_DIR / f"{unit.id}.done"


def is_done(out_root: Path, unit: Unit) -> bool:
    """True when the unit's done marker holds its current digest and its output folder is there.

    A missing or malformed marker, another digest (changed inputs or options) or a missing
    output all mean: run it (again).
    """
    marker = done_path(out_root, unit)
    try:
        record = json.loads(marker.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(record, dict) and record.get("digest") == unit.digest() and Path(unit.out).is_dir()


def read_done(out_root: Path, unit: Unit) -> dict:
    """The result a finished unit recorded ({} when unreadable)."""
    try:
        return json.loads(done_path(out_root, unit).read_text(encoding="utf-8")).get("result") or {}
    except (OSError, ValueError, AttributeError):
        return {}


def run_unit(unit: Unit, out_root: str) -> dict:
    """Run one unit on this worker: its output written atomically, then its done marker.

    Returns:
        {"unit": id, "frames": n, "seconds": wall s, "cpu_s": this process's CPU s, "rss_mb": [(s, MB), ...] samples of this
        process's resident memory while the unit ran, plus the kind's own figures}.

    Raises:
        Whatever the unit's work raises (the engine retries, then reports it).
    """
    import cv2

    from broadtrack_graph.actions import track_stages  # the tracking stack: imported on the worker only

    # One unit per core: OpenCV's own thread pool (as many threads as cores by default) would let a
    # single worker spread over every core and the workers fight over them (Ray sets OMP_NUM_THREADS=1
    # on its workers for the same reason). The frame prefetch thread stays: it overlaps decoding.
    cv2.setNumThreads(1)
    if os.environ.get("BROADTRACK_FAIL_UNIT") == unit.id:  # tests and the bench inject a failure here
        raise RuntimeError(f"failure injected into unit {unit.id}")
    final = Path(unit.out)
    temp = final.parent / f".{final.name}.tmp-{uuid.uuid4().hex[:8]}"
    temp.parent.mkdir(parents=True, exist_ok=True)
    sampler = _RssSampler()
    started, cpu_started = time.perf_counter(), time.process_time()
    try:
        with sampler:
            result = track_stages.STAGES[unit.kind](unit, temp)
        if final.exists():
            shutil.rmtree(final)
        os.replace(temp, final)
    finally:
        if temp.exists():
            shutil.rmtree(temp, ignore_errors=True)
    result = {"unit": unit.id, "frames": unit.frames, "seconds": round(time.perf_counter() - started, 3),
              "cpu_s": round(time.process_time() - cpu_started, 3),
              "rss_mb": sampler.samples, "pid": os.getpid(), "host": os.uname().nodename, **(result or {})}
    marker = done_path(Path(out_root), unit)
    marker.parent.mkdir(parents=True, exist_ok=True)
    write_json_atomic(marker, {"digest": unit.digest(), "result": result})
    return result


def rss_mb() -> float:
    """Resident memory of this process, MB (Linux /proc; 0 elsewhere)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as handle:
            return int(handle.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6
    except (OSError, ValueError, IndexError):
        return 0.0


class _RssSampler:
    """Samples :func:`rss_mb` every RSS_SAMPLE_S seconds in a thread, and once at the start and the end."""

    def __init__(self) -> None:
        self.samples: list[tuple[float, float]] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def _loop(self) -> None:
        while not self._stop.wait(RSS_SAMPLE_S):
            self.samples.append((round(time.perf_counter() - self._t0, 1), round(rss_mb(), 1)))

    def __enter__(self) -> "_RssSampler":
        self._t0 = time.perf_counter()
        self.samples.append((0.0, round(rss_mb(), 1)))
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()
        self.samples.append((round(time.perf_counter() - self._t0, 1), round(rss_mb(), 1)))
