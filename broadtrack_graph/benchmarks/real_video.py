"""The real-video section of ``bench real``: every video of a folder tracked online end to end.

Per clip: frames, frames with a camera, the alignment of those cameras with the visible
lines by a check that does not use the tracker's detector
(:mod:`broadtrack_graph.metrics.line_alignment`), the share of the main-camera frames with
an aligned camera, re-initialisations (per 100 frames), other-view frames, cuts, cameras
written on frames known to be another view, fps and stage timings, and the reliability of the
written cameras (their confidence against the alignment check,
:mod:`broadtrack_graph.metrics.reliability`; pooled over the clips too); an overlay video per
clip is written beside the runs (never inside the repository). With ``--shadow KEPT`` every
clip is tracked under a stand's shadow keeping that share of the light
(:mod:`broadtrack_graph.benchmarks.shadow`), with ``--degrade W:Q:N`` as a lower-league feed shows it
(:mod:`broadtrack_graph.benchmarks.degrade`), with ``--zoom Z`` as a lens Z times longer shows it
(:mod:`broadtrack_graph.benchmarks.zoom`), or several of them in that order
(:mod:`broadtrack_graph.benchmarks.clip_copy`); the cameras tracked on such a copy are scored on the original
frames (zoomed as the copy is: a zoom is the view itself, not a loss of it), and with a zoom the clip is tracked on
its whole frames too, whose cameras say which zoomed frames' markings fix a camera (``determinable``) and how far
the zoomed copy's cameras lie from them (``against_whole_frames``: the crop keeps the camera); the clip followed by a
cut to its zoomed frames is tracked too (``cut_to_zoom``: the zoomed shot against the wide one). With
``--starts STEP`` every clip is also tracked from
nothing from every STEP-th frame (:mod:`broadtrack_graph.benchmarks.real_starts`: how soon a shot's camera is found).
"""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.actions.track import track_input
from broadtrack_graph.benchmarks.clip_copy import chained, write_copy
from broadtrack_graph.benchmarks.degrade import degrade_change
from broadtrack_graph.benchmarks.options import tracker_options
from broadtrack_graph.benchmarks.real_starts import score_starts, start_frames, starts_figures, track_starts
from broadtrack_graph.benchmarks.shadow import shadow_change
from broadtrack_graph.benchmarks.zoom import (
    camera_agreement,
    cut_figures,
    determinable_figures,
    write_zoom_cut,
    zoom_change,
    zoom_label,
    zoomed_size,
)
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import fitting_curves
from broadtrack_graph.io.run_folder import RunFolder, read_frame_camera_ids
from broadtrack_graph.io.shots_file import SHOTS_FILE, read_shots
from broadtrack_graph.metrics.line_alignment import AlignmentConfig, line_alignment, line_pixels
from broadtrack_graph.metrics.reliability import merged_summaries, reliability_summary
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.types.status import FrameStatus

SHIFTED_TILT_DEG = 0.3
"""Every scored camera is also scored tilted by this much: the share of those passing is the check's false-accept rate."""

KNOWN_OTHER_VIEWS = {"jpn-tjk-360p-with-cut": [(480, 586)]}
"""Frames known not to show the main camera in the shared clips (start, end exclusive), by clip name."""


def has_video_data(args) -> bool:
    return Path(args.video_dir).is_dir() and any(Path(args.video_dir).glob("*.mp4"))


def run_video_clips(args) -> dict:
    """Track (or re-score) every clip and return {"clips": {name: figures}}; see the module docstring."""
    clips = sorted(Path(args.video_dir).glob("*.mp4"))
    if args.clips:
        clips = [c for c in clips if c.stem in set(args.clips)]
    kept, degradation, zoom = getattr(args, "shadow", None), getattr(args, "degrade", None), getattr(args, "zoom", None)
    changes, suffix = [], ""
    if kept is not None:
        changes.append(shadow_change(kept))
        suffix += f"-shadow-{kept:g}"
    if zoom is not None:
        changes.append(zoom_change(zoom))
        suffix += f"-{zoom_label(zoom)}"
    if degradation is not None:
        changes.append(degrade_change(degradation))
        suffix += f"-{degradation.label}"
    report, start_rows = {}, []
    step, length = getattr(args, "starts", None), getattr(args, "start_frames", 15)
    for video in clips:
        # A changed copy (--shadow, --zoom, --degrade) is tracked, its cameras scored on the original frames, zoomed
        # as the copy is (a copy of its own when the copy is changed in other ways too).
        name = video.stem + suffix
        run_dir = (Path(args.runs) if args.runs is not None else Path(args.out)) / name
        tracked = video if not changes else Path(args.out) / "copies" / f"{name}.mp4"
        scored = video
        if zoom is not None:
            scored = tracked if len(changes) == 1 else Path(args.out) / "copies" / f"{video.stem}-{zoom_label(zoom)}.mp4"
        if args.runs is None:
            if changes:
                write_copy(video, tracked, chained(*changes))
            track_input(tracked, run_dir, TrackingConfig(mode="online", **tracker_options(args)), end=args.end,
                        progress=not args.no_progress)
        fresh = args.runs is None and scored != tracked  # the zoom alone, beside a copy changed in other ways too
        if scored != video and (fresh or not scored.is_file()):
            write_copy(video, scored, zoom_change(zoom))
        report[name] = score_clip(scored, run_dir, args.score_every, end=args.end,
                                  other_views=KNOWN_OTHER_VIEWS.get(video.stem, []))
        if zoom is not None:
            report[name].update(_zoom_figures(video, run_dir, zoom, args))
        if step is not None:
            starts = start_frames(report[name]["frames_decoded"], step, length, KNOWN_OTHER_VIEWS.get(video.stem, []))
            runs = track_starts(tracked, Path(args.out) / "starts" / name, starts, length, tracker_options(args),
                                progress=False)
            rows = score_starts(scored, runs)
            report[name]["starts"] = starts_figures(rows, step, length)
            start_rows += rows
        if not args.no_overlay and tracked.is_file():
            from broadtrack_graph.products.overlay import write_overlay

            overlay = Path(args.out) / f"{name}_overlay.mp4"
            write_overlay(run_dir, tracked, overlay, end=args.end, progress=not args.no_progress)
            report[name]["overlay"] = str(overlay)
    pooled = merged_summaries([figures.get("reliability") for figures in report.values()])
    section = {"clips": report, "reliability": pooled}
    if step is not None:
        section["starts"] = {key: value for key, value in starts_figures(start_rows, step, length).items()
                             if key not in ("rows", "not_placed")}
    if kept is not None:
        section["shadow_kept"] = kept
    if degradation is not None:
        section["degraded"] = degradation.label
    if zoom is not None:
        section["zoom"] = zoom
        figures = [clip["determinable"] for clip in report.values()]
        fixed, found = sum(f["determinable"] for f in figures), sum(f["determinable_with_camera"] for f in figures)
        section["determinable"] = {"determinable": fixed, "determinable_with_camera": found,
                                   "share": round(found / fixed, 4) if fixed else None}
        cuts = [clip["cut_to_zoom"] for clip in report.values()]
        placed = sum(cut["with_camera"] for cut in cuts)
        same = sum(round(cut["same_id_share"] * cut["with_camera"]) for cut in cuts if cut["same_id_share"] is not None)
        section["cut_to_zoom"] = {"zoomed_frames_with_camera": placed, "same_id_share": round(same / placed, 4)
                                  if placed else None}
    return section


def _zoom_figures(video: Path, zoomed_dir: Path, zoom: float, args) -> dict:
    """A zoomed copy's figures beside its clip's own (module docstring): the clip tracked on its whole frames says
    which zoomed frames' markings fix a camera and where its cameras stand; the clip followed by a cut to its zoomed
    frames enlarged to its size puts the zoomed shot on the wide one's tripod, or not. Runs read from ``--runs`` or
    tracked under ``--out``."""
    runs = Path(args.runs) if args.runs is not None else Path(args.out)
    config = TrackingConfig(mode="online", **tracker_options(args))
    whole_dir = runs / video.stem
    if args.runs is None:
        track_input(video, whole_dir, config, end=args.end, progress=not args.no_progress)
    whole, zoomed = _cameras(whole_dir), _cameras(zoomed_dir)
    cut_name = f"{video.stem}-{zoom_label(zoom)}-cut"
    cut_video, cut_dir = Path(args.out) / "copies" / f"{cut_name}.mp4", runs / cut_name
    if args.runs is None:
        wide_frames, factor = write_zoom_cut(video, cut_video, zoom, end=args.end)
        track_input(cut_video, cut_dir, config, progress=not args.no_progress)
    else:  # the run says the cut's length (its two shots as long) and size (the crop's factor)
        summary = RunFolder(cut_dir).read_summary()
        wide_frames = summary["frames_written"] // 2
        factor = summary["width_px"] / zoomed_size(summary["width_px"], summary["height_px"], zoom)[0]
    return {"determinable": determinable_figures(whole, zoomed, zoom),
            "against_whole_frames": camera_agreement(whole, zoomed),
            "cut_to_zoom": cut_figures(_cameras(cut_dir), read_frame_camera_ids(cut_dir), wide_frames, factor)}


def _cameras(run_dir: Path) -> dict:
    """Frame index -> the camera a run wrote (None: none)."""
    return {record.frame_index: record.camera for record in RunFolder(run_dir).read_track().records}


def score_clip(video: Path, run_dir: Path, score_every: int = 1, config: AlignmentConfig = AlignmentConfig(),
               end: int | None = None, other_views=None) -> dict:
    """The figures of one tracked clip (module docstring), from its run folder and its frames (those before ``end``);
    ``other_views``: its frames known to show no main camera ((start, end exclusive) ranges; default: the
    :data:`KNOWN_OTHER_VIEWS` of the video's name)."""
    folder = RunFolder(run_dir)
    records = {r.frame_index: r for r in folder.read_track().records if end is None or r.frame_index < end}
    summary = folder.read_summary() if folder.has_summary() else {}
    known = KNOWN_OTHER_VIEWS.get(video.stem, []) if other_views is None else other_views
    other_known = {i for a, b in known for i in range(a, b)}
    other_found = {i for i, r in records.items() if r.status == FrameStatus.OTHER_VIEW}
    curves = fitting_curves(PitchTemplate())
    capture = cv2.VideoCapture(str(video))
    scores, shifted, scored = {}, {}, []
    index = 0
    last = max(records) if records else -1
    while index <= last:
        ok, image = capture.read()
        if not ok:
            break
        record = records.get(index)
        if record is not None and record.camera is not None and index % max(1, score_every) == 0:
            scored.append(index)
            pixels = line_pixels(image, config)
            # at the frame's size (a degraded copy's cameras are at the copy's)
            camera = record.camera.rescaled(image.shape[1], image.shape[0])
            alignment = line_alignment(image, camera, curves, config, pixels)
            if alignment is not None:
                scores[index] = alignment
                # The check must reject wrong cameras too: the same camera tilted by SHIFTED_TILT_DEG.
                turned = camera.replace(tilt_rad=camera.tilt_rad + math.radians(SHIFTED_TILT_DEG))
                shifted[index] = line_alignment(image, turned, curves, config, pixels)
        index += 1
    capture.release()
    decoded = index
    main = [i for i in range(decoded) if i not in other_known and i not in other_found and i in records]
    main_scored = [i for i in main if i % max(1, score_every) == 0]

    def share(selected, aligned) -> float:
        return round(sum(1 for i in selected if aligned(i)) / max(len(selected), 1), 3)

    def visible(i, table=scores) -> bool:
        return table.get(i) is not None and table[i].aligned(config)

    def all_markings(i) -> bool:
        return i in scores and scores[i].all_markings >= config.aligned_share

    with_camera = sum(1 for r in records.values() if r.camera is not None)
    reinits = sum(1 for r in records.values() if r.reinitialised)
    frames = len(records)
    shots = read_shots(run_dir / SHOTS_FILE) if (run_dir / SHOTS_FILE).is_file() else []
    return {
        "frames": frames,
        "frames_decoded": decoded,
        "frames_with_camera": with_camera,
        "other_view_frames": len(other_found),
        "cuts": max(0, len(shots) - 1) if shots else summary.get("cuts"),
        "shots": [[s.start, s.end, s.kind] for s in shots],
        "reinitialisations": reinits,
        "reinit_per_100_frames": round(100.0 * reinits / max(frames, 1), 2),
        "alignment_mean": round(float(np.mean([a.visible_markings for a in scores.values()])), 3) if scores else None,
        "aligned_share_of_camera_frames": share(scored, visible),
        "main_frames_aligned_share": share(main_scored, visible),
        "main_frames_aligned_share_all_markings": share(main_scored, all_markings),
        f"main_frames_aligned_share_tilted_{SHIFTED_TILT_DEG}deg": share(main_scored, lambda i: visible(i, shifted)),
        "reliability": reliability_summary([np.nan if records[i].confidence is None else records[i].confidence
                                            for i in scores], [visible(i) for i in scores]),
        "cameras_on_known_other_view_frames": sum(1 for i in other_known if i in records and records[i].camera is not None),
        "status_counts": summary.get("status_counts"),
        "fps": summary.get("fps"),
        "cpu_ms_per_frame": summary.get("cpu_ms_per_frame"),
        "cores_used": summary.get("cores_used"),
        "timings_s": summary.get("timings_s"),
        "solver_restarts": summary.get("solver_restarts"),
    }
