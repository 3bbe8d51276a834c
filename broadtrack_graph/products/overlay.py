"""The projected pitch drawn on frames, coloured by confidence, with a text panel and a bird's-eye inset.

Drawing functions (:func:`project_pitch_polylines`, :func:`draw_pitch`,
:func:`draw_info_panel`, :func:`render_overlay_frame`) take and return arrays;
:func:`write_overlay` reads a run and an input clip and writes an mp4 or PNGs.

Projection for drawing: every class (26, goals included) is sampled every
``step_m`` metres, projected with the camera's full distortion model, and cut
where a point is behind the camera or beyond the image's field of view plus a
margin: with k1 < 0 the radial model folds back past its turning radius, and a
point far outside the image would otherwise land inside it. OpenCV clips the
remaining polylines to the image.
"""

from __future__ import annotations

import logging
import math
from functools import lru_cache
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.distortion import distort_normalized, undistort_normalized
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate

logger = logging.getLogger(__name__)

DRAW_STEP_M = 0.25
"""Sampling step of the template for drawing, metres."""

FIELD_MARGIN = 0.3
"""Points are kept up to (1 + FIELD_MARGIN) times the image's corner radius (normalised coordinates)."""

NO_CONFIDENCE_BGR = (230, 230, 230)
"""Colour of a camera whose confidence is unknown."""

CONFIDENCE_RED_AT = 0.3
CONFIDENCE_GREEN_AT = 0.9


def confidence_colour_bgr(confidence: float | None) -> tuple[int, int, int]:
    """BGR colour of a confidence: red at <= 0.3, yellow at 0.6, green at >= 0.9; light grey when unknown.

    The tracker re-initialises below 0.5, which falls in the orange.
    """
    if confidence is None or not math.isfinite(confidence):
        return NO_CONFIDENCE_BGR
    t = min(1.0, max(0.0, (confidence - CONFIDENCE_RED_AT) / (CONFIDENCE_GREEN_AT - CONFIDENCE_RED_AT)))
    if t < 0.5:
        return (0, int(round(255 * 2 * t)), 255)
    return (0, 255, int(round(255 * (2 - 2 * t))))


@lru_cache(maxsize=8)
def _samples(step_m: float, dimensions) -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
    template = PitchTemplate(dimensions)
    samples = template.sample_uniform(step_m, LINE_CLASSES)
    names = tuple(samples)
    points_w = np.vstack([samples[n] for n in names])
    offsets = np.concatenate([[0], np.cumsum([len(samples[n]) for n in names])])
    points_w.setflags(write=False)
    return names, points_w, offsets


def _undistorted_radius_limit(camera: Camera, margin: float) -> float:
    """Largest undistorted normalised radius drawn: the image corner plus a margin, inside the fold-back of k1 < 0."""
    corner = np.array([[camera.width_px, camera.height_px]], dtype=float) - camera.principal_point
    corner_d = np.abs(corner) / camera.focal_px * (1.0 + margin)
    if camera.extra_distortion.is_zero and camera.k1 < 0:
        r_turn = 1.0 / math.sqrt(-3.0 * camera.k1)
        if float(np.hypot(*corner_d[0])) >= (2.0 / 3.0) * r_turn:
            return 0.98 * r_turn
    r_n = undistort_normalized(corner_d, camera.k1, camera.extra_distortion)
    return float(np.hypot(*r_n[0]))


def project_pitch_polylines(
    camera: Camera,
    template: PitchTemplate | None = None,
    step_m: float = DRAW_STEP_M,
    margin: float = FIELD_MARGIN,
) -> dict[str, list[np.ndarray]]:
    """Projected pitch markings for drawing, cut into visible pieces.

    Args:
        camera: the camera (pixels at its own resolution).
        template: the pitch (default 105 x 68).
        step_m: sampling step along every marking, metres.
        margin: how far past the image corners points are kept (fraction of the corner radius).

    Returns:
        class name -> list of (K, 2) pixel polylines (K >= 2), in the image or a little
        past its border; classes with nothing in view are absent.
    """
    names, points_w, offsets = _samples(float(step_m), (template or PitchTemplate()).dimensions)
    points_c = camera.world_to_camera(points_w)
    depth = points_c[:, 2]
    in_front = depth > 1e-3
    with np.errstate(divide="ignore", invalid="ignore"):
        xy_n = points_c[:, :2] / np.where(in_front, depth, np.nan)[:, None]
    r_limit = _undistorted_radius_limit(camera, margin)
    with np.errstate(invalid="ignore"):
        valid = in_front & (np.hypot(xy_n[:, 0], xy_n[:, 1]) < r_limit)
    uv = np.full_like(xy_n, np.nan)
    if valid.any():
        uv[valid] = camera.focal_px * distort_normalized(xy_n[valid], camera.k1, camera.extra_distortion) + camera.principal_point
    out: dict[str, list[np.ndarray]] = {}
    for j, name in enumerate(names):
        start, stop = offsets[j], offsets[j + 1]
        keep = valid[start:stop]
        if keep.sum() < 2:
            continue
        # Runs of consecutive valid points.
        edges = np.diff(np.concatenate([[0], keep.astype(np.int8), [0]]))
        run_starts, run_stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        pieces = [uv[start + a:start + b] for a, b in zip(run_starts, run_stops) if b - a >= 2]
        if pieces:
            out[name] = pieces
    return out


def draw_pitch(
    image_bgr: np.ndarray,
    camera: Camera,
    colour_bgr: tuple[int, int, int] = (0, 255, 0),
    thickness_px: int | None = None,
    template: PitchTemplate | None = None,
    antialias: bool = True,
) -> np.ndarray:
    """Draw the projected pitch on an image (in place; also returned).

    Args:
        image_bgr: (H, W, 3) uint8 image at the camera's resolution (the camera is
            rescaled to the image width if it is not).
        camera: the camera.
        colour_bgr: line colour (see :func:`confidence_colour_bgr`).
        thickness_px: line width (default: 2 px at 1920 wide, at least 1).
        template: the pitch (default 105 x 68).
        antialias: anti-aliased lines (off gives exact, hard-edged pixels).
    """
    height, width = image_bgr.shape[:2]
    camera = camera.rescaled(width, height)
    thickness = thickness_px or max(1, int(round(2 * width / 1920)))
    polylines = [
        np.round(piece * 16).astype(np.int32)
        for pieces in project_pitch_polylines(camera, template).values()
        for piece in pieces
    ]
    if polylines:
        cv2.polylines(image_bgr, polylines, False, colour_bgr, thickness, cv2.LINE_AA if antialias else cv2.LINE_8, shift=4)
    return image_bgr


def draw_info_panel(image_bgr: np.ndarray, lines: list[str], corner: str = "top-left",
                    colour_bgr: tuple[int, int, int] = (255, 255, 255)) -> np.ndarray:
    """Write a few lines of text on a dark translucent box in a corner (in place; also returned)."""
    height, width = image_bgr.shape[:2]
    scale = max(0.35, 0.6 * width / 1920)
    thickness = max(1, int(round(width / 1200)))
    sizes = [cv2.getTextSize(line, cv2.FONT_HERSHEY_SIMPLEX, scale, thickness)[0] for line in lines]
    line_h = int(max((s[1] for s in sizes), default=10) * 1.8)
    pad = max(4, line_h // 3)
    box_w = max((s[0] for s in sizes), default=0) + 2 * pad
    box_h = line_h * len(lines) + pad
    x0 = pad if corner.endswith("left") else width - pad - box_w
    y0 = pad if corner.startswith("top") else height - pad - box_h
    x1, y1 = min(width, x0 + box_w), min(height, y0 + box_h)
    region = image_bgr[max(0, y0):y1, max(0, x0):x1]
    region[:] = (region.astype(np.uint16) * 2 // 5).astype(np.uint8)
    for k, line in enumerate(lines):
        baseline_y = y0 + (k + 1) * line_h - line_h // 4
        cv2.putText(image_bgr, line, (x0 + pad, baseline_y), cv2.FONT_HERSHEY_SIMPLEX, scale, colour_bgr, thickness, cv2.LINE_AA)
    return image_bgr


def record_panel_lines(record) -> list[str]:
    """Text panel of a :class:`~broadtrack_graph.io.run_folder.TrackRecord`."""
    time_text = "" if record.time_s is None else f"  t {record.time_s:.2f} s"
    lines = [f"frame {record.frame_id}{time_text}"]
    cam = record.camera
    if cam is None:
        lines.append(f"no camera: {record.status}")
        if record.reason:
            lines.append(record.reason[:60])
        return lines
    lines.append(f"pan {cam.pan_deg:.2f}  tilt {cam.tilt_deg:.2f}  roll {cam.roll_deg:.2f} deg")
    lines.append(f"f {cam.focal_px:.0f} px  k1 {cam.k1:+.3f}")
    c = cam.position_m
    lines.append(f"C ({c[0]:.1f}, {c[1]:.1f}, {c[2]:.1f}) m")
    confidence = "-" if record.confidence is None else f"{record.confidence:.2f}"
    lines.append(f"confidence {confidence}  {record.status}{'  [re-init]' if record.reinitialised else ''}")
    return lines


def render_overlay_frame(
    image_bgr: np.ndarray,
    record,
    view=None,
    inset: bool = True,
    template: PitchTemplate | None = None,
    players=None,
) -> np.ndarray:
    """A frame with the projected pitch, the text panel and the bird's-eye inset.

    Args:
        image_bgr: (H, W, 3) uint8 frame (not modified).
        record: the frame's :class:`~broadtrack_graph.io.run_folder.TrackRecord`, or None
            when the run has no entry for it.
        view: a :class:`~broadtrack_graph.products.birdseye.BirdseyeView` kept for a whole video.
        inset: draw the bird's-eye inset (top right).
        players: this frame's players for the inset, ``(PlayerPositions, rows (K,) int)``, or None.

    Returns:
        (H, W, 3) uint8 new image.
    """
    from broadtrack_graph.products.birdseye import draw_birdseye, place_inset

    out = image_bgr.copy()
    camera = None if record is None else record.camera
    colour = confidence_colour_bgr(None if record is None else record.confidence)
    if camera is not None:
        draw_pitch(out, camera, colour, template=template)
    lines = ["no estimate in the run"] if record is None else record_panel_lines(record)
    draw_info_panel(out, lines)
    if inset:
        if camera is not None:
            camera = camera.rescaled(out.shape[1], out.shape[0])
        picture = draw_birdseye(camera, view, template=template, footprint_bgr=colour)
        if players is not None and view is not None:
            from broadtrack_graph.products.players_view import draw_players

            positions, rows = players
            draw_players(picture, view, positions.xy_m[rows], positions.track_id[rows],
                         [positions.teams[i] for i in rows], [positions.roles[i] for i in rows], labels=False)
        place_inset(out, picture, "top-right")
    return out


def write_overlay(
    run_dir: str | Path,
    frames_input: str | Path,
    out_path: str | Path,
    start: int | None = None,
    end: int | None = None,
    inset: bool = True,
    progress: bool = True,
    players_path: str | Path | None = None,
) -> dict:
    """Draw a run on its input frames and write an mp4 (``*.mp4``) or a folder of PNGs.

    Frames are matched to the run's records by frame id; a frame the run has no
    record for is drawn with "no estimate in the run"; an unreadable input frame is
    written black with its problem in the panel (so the video keeps its timing).

    Args:
        run_dir: run folder (track.jsonl) or folder of camera files.
        frames_input: video, image folder or game-state sequence (as ``track`` takes).
        out_path: ``something.mp4`` (cv2 mp4v) or a folder for ``overlay_<frame_id>.png``.
        start, end: window of input frames (0-based, end exclusive).
        players_path: a ``players.jsonl`` (or its folder) whose players are drawn in the inset.

    Returns:
        {"out": path, "frames": written, "with_camera": drawn with a camera, "missing_input": unreadable}.

    Raises:
        InputError: run or input cannot be read, output cannot be written.
    """
    from tqdm import tqdm

    from broadtrack_graph.errors import InputError
    from broadtrack_graph.io.decode_summary import decodable_frames
    from broadtrack_graph.io.frames import open_frames
    from broadtrack_graph.io.run_folder import read_track
    from broadtrack_graph.io.video import open_video_writer
    from broadtrack_graph.products.birdseye import BirdseyeView

    track = read_track(run_dir)
    records = track.by_frame_id()
    players_rows: dict[str, list[int]] = {}
    positions = None
    if players_path is not None:
        from broadtrack_graph.io.players_file import read_players_file

        positions = read_players_file(players_path)
        for i, frame_id in enumerate(positions.frame_ids):
            players_rows.setdefault(frame_id, []).append(i)
    out_path = Path(out_path)
    as_video = out_path.suffix.lower() == ".mp4"
    cam_positions = np.array([r.camera.position_m for r in track.records if r.camera is not None]).reshape(-1, 3)
    counts = {"frames": 0, "with_camera": 0, "missing_input": 0}
    writer = None
    with open_frames(frames_input, start, end) as source:
        view = BirdseyeView.fitting(480, camera_positions_w=np.median(cam_positions, axis=0)[None] if len(cam_positions) else None)
        if as_video:
            writer = open_video_writer(out_path, source.fps, (source.width_px, source.height_px))
        else:
            try:
                out_path.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise InputError(out_path, f"cannot create output folder: {exc.strerror or exc}") from None
        try:
            for frame in tqdm(decodable_frames(source), total=len(source), desc="overlay", unit="frame", disable=not progress):
                record = records.get(frame.frame_id)
                if frame.image_bgr is None:
                    image = np.zeros((source.height_px, source.width_px, 3), dtype=np.uint8)
                    draw_info_panel(image, [f"frame {frame.frame_id}", f"unreadable input: {frame.problem}"[:70]])
                    counts["missing_input"] += 1
                else:
                    players = None
                    if positions is not None:
                        players = (positions, np.array(players_rows.get(frame.frame_id, []), dtype=int))
                    image = render_overlay_frame(frame.image_bgr, record, view, inset, players=players)
                    counts["with_camera"] += int(record is not None and record.camera is not None)
                if writer is not None:
                    writer.write(image)
                elif not cv2.imwrite(str(out_path / f"overlay_{frame.frame_id}.png"), image):
                    raise InputError(out_path, f"cannot write overlay_{frame.frame_id}.png")
                counts["frames"] += 1
        finally:
            if writer is not None:
                writer.release()
    if counts["frames"] and not counts["with_camera"]:
        if len(cam_positions):
            logger.warning("%s: no input frame matched a camera of the run (frame ids differ?)", run_dir)
        else:
            logger.warning("%s: the run has no camera: the frames are drawn without one", run_dir)
    return {"out": str(out_path), "cameras_from": str(track.path), **counts}
