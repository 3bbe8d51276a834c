"""Track many clips (a season) in parallel units of work, resumably: the action behind ``track-many``.

:func:`plan_units` turns clips into units (:mod:`broadtrack_graph.actions.track_units`): a
clip in online or fixed-lag mode, or a short one in batch mode, is one unit; a long clip in
batch mode from a detections file is staged: online first passes over windows in parallel ->
one tripod fit (the reduce) -> batch refinement of the windows in parallel with that tripod ->
stitch. :func:`track_many` runs the units stage by stage on an engine (Ray, or the one-process
:class:`~broadtrack_graph.actions.parallel.SerialEngine`), skipping units already done with
the same inputs and options, retrying failures, reporting the units that still fail while the
others finish, with one progress bar over all frames; it writes ``OUT/track_many.json``.
"""

from __future__ import annotations

import hashlib
import logging
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

from broadtrack_graph.actions.track_units import WORK_DIR, Unit, is_done, read_done, run_unit
from broadtrack_graph.io.detections import detections_frame_range
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.io.manifest import ClipSpec
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.track.chunks import plan_chunks
from broadtrack_graph.track.config import TrackingConfig

logger = logging.getLogger(__name__)

REPORT_FILE = "track_many.json"


@dataclass(frozen=True)
class ManyOptions:
    """How track-many cuts and runs the work."""

    chunk_frames: int = 1500  # batch mode: a detections-file clip longer than 1.25x this is refined in windows
    overlap_frames: int = 50  # frames a window reaches into each neighbour (solved, not kept)
    retries: int = 2  # extra attempts of a failing unit
    progress: bool = True  # one tqdm bar over all frames of all units


@dataclass
class ManyReport:
    """What a track-many job did."""

    clips: list[dict] = field(default_factory=list)  # per clip: name, frames, completeness, mean_confidence, fps
    ran: list[str] = field(default_factory=list)  # unit ids run now
    skipped: list[str] = field(default_factory=list)  # unit ids already done
    failed: dict[str, str] = field(default_factory=dict)  # unit id -> one-line error
    not_run: list[str] = field(default_factory=list)  # unit ids whose inputs failed
    stale_removed: int = 0  # temporary folders of units killed in an earlier run, removed
    results: dict[str, dict] = field(default_factory=dict)  # unit id -> its figures (this run or recorded)
    wall_s: float = 0.0

    def as_dict(self) -> dict:
        return dict(self.__dict__)


def plan_units(clips: list[ClipSpec], out_root: str | Path, config: TrackingConfig,
               options: ManyOptions = ManyOptions()) -> list[Unit]:
    """Units of work of a job, in stage order (see the module docstring)."""
    out_root = Path(out_root).resolve()
    units: list[Unit] = []
    for clip in clips:
        clip_config = config if clip.mode is None else _with_mode(config, clip.mode)
        spec = {"clip": _absolute(clip).as_dict(), "config": clip_config}
        chunk_frames = clip.chunk_frames or options.chunk_frames
        staged = clip_config.mode == "batch" and clip.input is None and clip.detections is not None
        if staged:
            first, end = detections_frame_range(clip.detections)
            start = first if clip.start is None else clip.start
            end = end if clip.end is None else min(end, clip.end)
            staged = end - start > 1.25 * chunk_frames
        if not staged:
            units.append(Unit(f"{clip.name}.track", clip.name, "track", 0, _frames_hint(clip), str(out_root / clip.name),
                              spec))
            continue
        work = out_root / WORK_DIR / clip.name
        chunks = plan_chunks(start, end, chunk_frames, options.overlap_frames)
        pass1 = [Unit(f"{clip.name}.pass1-{c.index:03d}", clip.name, "pass1", 0, c.hi - c.lo,
                      str(work / f"pass1-{c.index:03d}"), {**spec, "chunk": c.as_dict()}) for c in chunks]
        pieces = [(c.as_dict(), u.out) for c, u in zip(chunks, pass1)]
        tripod = _after(Unit(f"{clip.name}.tripod", clip.name, "tripod", 1, 0, str(work / "tripod"),
                             {**spec, "pass1": pieces}), pass1)
        refine = [_after(Unit(f"{clip.name}.refine-{c.index:03d}", clip.name, "refine", 2, c.hi - c.lo,
                              str(work / f"refine-{c.index:03d}"),
                              {**spec, "chunk": c.as_dict(), "pass1": pieces, "tripod_dir": tripod.out}),
                         pass1 + [tripod]) for c in chunks]
        stitch = _after(Unit(f"{clip.name}.stitch", clip.name, "stitch", 3, 0, str(out_root / clip.name),
                             {**spec, "pass1": pieces, "tripod_dir": tripod.out,
                              "refine": [(c.as_dict(), u.out) for c, u in zip(chunks, refine)]}), refine + [tripod])
        units += pass1 + [tripod] + refine + [stitch]
    return units


def track_many(clips: list[ClipSpec], out_root: str | Path, config: TrackingConfig = TrackingConfig(),
               options: ManyOptions = ManyOptions(), engine=None) -> ManyReport:
    """Run (or finish) a job: every unit not yet done, stage by stage, on ``engine``.

    Args:
        clips: the clips (from a manifest or the command line).
        out_root: the job's folder: one run folder per clip, ``_units/`` (done markers),
            ``_work/`` (stage outputs of staged clips), ``track_many.json``.
        config: tracking options of clips that set none of their own.
        engine: an entered engine (``RayEngine`` / ``SerialEngine``); None runs in this process.

    Returns:
        The report (also written to ``OUT/track_many.json``); failures are listed, not raised.
    """
    from tqdm import tqdm

    from broadtrack_graph.actions.parallel import SerialEngine

    out_root = Path(out_root).resolve()
    out_root.mkdir(parents=True, exist_ok=True)
    engine = engine or SerialEngine(options.retries)
    units = plan_units(clips, out_root, config, options)
    report = ManyReport()
    report.stale_removed = remove_stale_temps(units)
    started = time.perf_counter()
    bar = tqdm(total=sum(u.frames for u in units), unit="frame", desc=f"track-many ({engine.name})",
               disable=not options.progress)
    broken: set[str] = set()
    try:
        for stage in sorted({u.stage for u in units}):
            todo = []
            for unit in (u for u in units if u.stage == stage):
                if any(d in broken for d in unit.depends):
                    broken.add(unit.id)
                    report.not_run.append(unit.id)
                elif is_done(out_root, unit):
                    report.skipped.append(unit.id)
                    report.results[unit.id] = read_done(out_root, unit)
                    bar.update(unit.frames)
                else:
                    todo.append(unit)
            by_id = {u.id: u for u in todo}

            def done(key, result, by_id=by_id):
                report.ran.append(key)
                report.results[key] = result
                bar.update(by_id[key].frames)

            def failed(key, message, by_id=by_id):
                report.failed[key] = message
                broken.add(key)
                bar.update(by_id[key].frames)
                logger.warning("unit %s failed: %s", key, message)

            engine.run(run_unit, [(u.id, (u, str(out_root))) for u in todo], done, failed)
    finally:
        bar.close()
    report.wall_s = round(time.perf_counter() - started, 3)
    report.clips = [clip_row(name, out_root, [u for u in units if u.clip == name], report) for name in
                    dict.fromkeys(u.clip for u in units)]
    write_json_atomic(out_root / REPORT_FILE, {**report.as_dict(), "engine": engine.name,
                                               "workers": getattr(engine, "workers", None)}, indent=1)
    return report


def remove_stale_temps(units: list[Unit]) -> int:
    """Delete the temporary folders a killed run left beside the units' outputs; returns how many."""
    removed = 0
    for parent in {Path(u.out).parent for u in units}:
        if parent.is_dir():
            for stale in parent.glob(".*.tmp-*"):
                shutil.rmtree(stale, ignore_errors=True)
                removed += 1
    return removed


def clip_row(name: str, out_root: Path, units: list[Unit], report: ManyReport) -> dict:
    """One row of the summary table: frames, completeness, mean confidence, fps per worker-second."""
    row = {"clip": name, "frames": None, "completeness": None, "mean_confidence": None, "fps": None,
           "units": len(units), "failed": sum(u.id in report.failed for u in units)}
    folder = RunFolder(out_root / name)
    if folder.has_summary() and not row["failed"] and not any(u.id in report.not_run for u in units):
        summary = folder.read_summary()
        seconds = sum(float((report.results.get(u.id) or {}).get("seconds") or 0.0) for u in units)
        frames = summary.get("frames_written") or 0
        row.update(frames=frames, completeness=summary.get("completeness"),
                   mean_confidence=summary.get("mean_confidence"), fps=round(frames / seconds, 2) if seconds else None)
    return row


def _after(unit: Unit, depends: list[Unit]) -> Unit:
    """The unit depending on others; their digests enter its spec (a redone input redoes it)."""
    joined = hashlib.sha256("".join(d.digest() for d in depends).encode()).hexdigest()
    return Unit(unit.id, unit.clip, unit.kind, unit.stage, unit.frames, unit.out, {**unit.spec, "after": joined},
                tuple(d.id for d in depends))


def _absolute(clip: ClipSpec) -> ClipSpec:
    def resolved(path):
        return None if path is None else Path(path).resolve()

    return ClipSpec(clip.name, resolved(clip.input), resolved(clip.detections), resolved(clip.tripod), clip.start,
                    clip.end, clip.mode, clip.chunk_frames)


def _with_mode(config: TrackingConfig, mode: str) -> TrackingConfig:
    from dataclasses import replace

    return replace(config, mode=mode)


def _frames_hint(clip: ClipSpec) -> int:
    """Frames of a one-unit clip for the progress bar (exact for detections files, else the range or 1)."""
    if clip.detections is not None:
        first, end = detections_frame_range(clip.detections)
        first = first if clip.start is None else clip.start
        end = end if clip.end is None else min(end, clip.end)
        return max(1, end - first)
    if clip.start is not None and clip.end is not None:
        return clip.end - clip.start
    return _count_images(clip.input)


def _count_images(path: Path | None) -> int:
    if path is None or not Path(path).is_dir():
        return 1
    folder = Path(path) / "img1" if (Path(path) / "img1").is_dir() else Path(path)
    return max(1, sum(1 for p in folder.iterdir() if p.suffix.lower() in (".jpg", ".jpeg", ".png")))


def summary_table(report: ManyReport) -> str:
    """The per-clip table the command prints."""
    lines = [f"{'clip':<24} {'frames':>8} {'complete':>9} {'conf':>6} {'fps':>8}  units"]
    for row in report.clips:
        def fmt(value, spec):
            return "-" if value is None else format(value, spec)

        note = f"{row['units']}" + (f" ({row['failed']} failed)" if row["failed"] else "")
        lines.append(f"{row['clip']:<24} {fmt(row['frames'], 'd'):>8} {fmt(row['completeness'], '.3f'):>9} "
                     f"{fmt(row['mean_confidence'], '.3f'):>6} {fmt(row['fps'], '.1f'):>8}  {note}")
    return "\n".join(lines)
