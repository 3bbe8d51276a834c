"""What each kind of track-many unit does on its worker: paths in, files out (into ``temp``).

Called by :func:`~broadtrack_graph.actions.track_units.run_unit`, which renames ``temp`` into
place and records the unit as done. Each function takes the unit and the temporary folder and
returns a small dict of figures for the job's report.
"""

from __future__ import annotations

import logging
from dataclasses import replace
from pathlib import Path

from broadtrack_graph.actions.track import track_input
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.run_folder import RunFolder, read_track
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.io.tripod_file import read_tripod, write_tripod
from broadtrack_graph.track.chunked import fit_clip_tripod, refine_window_records
from broadtrack_graph.track.chunks import Chunk, stitch

logger = logging.getLogger(__name__)


def _path(value) -> Path | None:
    return None if value is None else Path(value)


def _known_tripod(clip: dict):
    return None if clip.get("tripod") is None else read_tripod(clip["tripod"])


def run_track(unit, temp: Path) -> dict:
    """A whole clip in its mode, as ``broadtrack-graph track`` would."""
    clip, config = unit.spec["clip"], unit.spec["config"]
    frames = _path(clip.get("input"))
    result = track_input(frames, temp, config, tripod=_known_tripod(clip), detections_path=_path(clip.get("detections")),
                         start=clip.get("start"), end=clip.get("end"), progress=False)
    return _summary_figures(result.summary)


def run_pass1(unit, temp: Path) -> dict:
    """The online first pass over one window (the frames of its neighbours included for warm-up)."""
    clip, chunk = unit.spec["clip"], Chunk(**unit.spec["chunk"])
    config = replace(unit.spec["config"], mode="online")
    result = track_input(None, temp, config, tripod=_known_tripod(clip), detections_path=_path(clip["detections"]),
                         start=chunk.lo, end=chunk.hi, progress=False)
    return _summary_figures(result.summary)


def run_tripod(unit, temp: Path) -> dict:
    """The reduce: one tripod for the clip (the known one, or fitted to every first-pass camera)."""
    clip = unit.spec["clip"]
    temp.mkdir(parents=True, exist_ok=True)
    tripod, info = _known_tripod(clip), {"known": clip.get("tripod")}
    if tripod is None:
        tripod, info = fit_clip_tripod(_pass1_records(unit.spec["pass1"]), unit.spec["config"])
    if tripod is not None:
        write_tripod(RunFolder(temp).tripod_path, tripod, info)
    else:
        logger.warning("%s: tripod fit failed (%s); refining without the tripod factor", unit.clip, info.get("reason"))
    return {"tripod": None if tripod is None else {"T_w": [float(v) for v in tripod.T_w],
                                                   "delta_m": float(tripod.delta_m)}}


def run_refine(unit, temp: Path) -> dict:
    """Batch refinement of one window with the clip's tripod held fixed."""
    clip, chunk, config = unit.spec["clip"], Chunk(**unit.spec["chunk"]), unit.spec["config"]
    tripod_file = RunFolder(unit.spec["tripod_dir"]).tripod_path
    tripod = read_tripod(tripod_file) if tripod_file.is_file() else None
    pieces = [(Chunk(**c), d) for c, d in unit.spec["pass1"]]
    needed = [(c, d) for c, d in pieces if c.keep_lo < chunk.hi and c.keep_hi > chunk.lo]
    records = [r for r in _pass1_records(needed) if chunk.lo <= r.frame_index < chunk.hi]
    detections = read_detections(clip["detections"], frame_range=(chunk.lo, chunk.hi))
    width, height = detections.image_size
    observations = {i: detections.frames[i] for i in range(chunk.lo, chunk.hi) if i in detections.frames}
    refined = refine_window_records(records, observations, width, height, config, tripod)
    writer = TrackWriter(temp, width, height, run_info={"unit": unit.id, "window": chunk.as_dict()})
    for record in refined:
        writer.write(record)
    return _summary_figures(writer.close())


def run_stitch(unit, temp: Path) -> dict:
    """Each refined window's own frames, in order, into the clip's run folder."""
    clip, config = unit.spec["clip"], unit.spec["config"]
    pieces = [(Chunk(**c), read_track(d).records) for c, d in unit.spec["refine"]]
    records = stitch(pieces)
    first = next((r.camera for r in records if r.camera is not None), None)
    width, height = (first.width_px, first.height_px) if first is not None else (1920, 1080)
    writer = TrackWriter(temp, width, height, also_960x540=config.write_960x540,
                         run_info={"input": clip.get("input"), "detections": clip.get("detections"), "mode": "batch",
                                   "staged": True, "chunks": len(pieces)})
    for record in records:
        writer.write(record)
    tripod_file = RunFolder(unit.spec["tripod_dir"]).tripod_path
    extra = {"pass1": str(Path(unit.spec["pass1"][0][1]).parent)}
    if tripod_file.is_file():
        tripod = read_tripod(tripod_file)
        RunFolder(temp).write_tripod(tripod)
        extra["tripod"] = {"T_w": [float(v) for v in tripod.T_w], "delta_m": float(tripod.delta_m)}
    return _summary_figures(writer.close(extra))


def _pass1_records(pieces) -> list:
    """Stitched first-pass records of the given (chunk, folder) pieces (chunk as Chunk or dict)."""
    loaded = [(c if isinstance(c, Chunk) else Chunk(**c), read_track(d).records) for c, d in pieces]
    return stitch(loaded)


def _summary_figures(summary: dict) -> dict:
    return {k: summary.get(k) for k in ("frames_written", "frames_with_camera", "completeness", "mean_confidence")}


STAGES = {"track": run_track, "pass1": run_pass1, "tripod": run_tripod, "refine": run_refine, "stitch": run_stitch}
"""Unit kind -> the function that runs it."""
