"""Writing synthetic clips to a folder in the SoccerNet game-state layout (and reading their truth back).

Layout of OUT (the same folder is a valid tracker input)::

    img1/000001.jpg ...                 frames
    Labels-GameState.json               pitch lines of every frame (supercategory "pitch") and
                                        player boxes (supercategory "object")
    annotations/000001.json             per-frame SoccerNet line annotation (none for a frame that shows
                                        no marking; it is listed with has_labeled_pitch false)
    cameras/camera_000001.json          ground-truth camera at the clip resolution
    masks/000001.png                    uint8: LINE_CLASSES index + 1 of the visible marking, 0 = none
    keypoints/000001.json               visible template keypoints {name: [u, v]} (pixels)
    players.json                        per-frame player boxes [[id, x0, y0, x1, y1], ...] (pixels)
    players_pitch.json                  true foot positions of every player in every frame (metres,
                                        pitch frame): {"fps", "track_ids", "roles", "teams",
                                        "frames": {frame_id: {track_id: [x, y]}}}; track_id = id + 1,
                                        the game-state labels' track_id
    tripod.json                         {"T_w": [x, y, z], "delta_m": d} (generated tracks only)
    ground_truth.json                   per frame: lambda_m, annotated, occluded / folded classes
    clip.json                           preset, seed, size, fps, frame counts, files
    clip.mp4                            optional (mp4v)

The ``broadcast`` preset (:mod:`broadtrack_graph.synth.broadcast`: hard cuts between several
tripod cameras, close-ups and crowd shots) writes cameras, annotations, keypoints and masks
for its pitch frames only, ``tripod.json`` of the main camera, ``camera_id`` and ``shot_kind``
per frame in ground_truth.json, and the truth files of :mod:`broadtrack_graph.io.broadcast_truth`
(shots_truth.json, tripods_truth.json, camera_ids_truth.json).

Frames are written as they are rendered (with a progress bar); the clip-level files
are written at the end, also after an interruption, so finished frames stay usable.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import GAMESTATE_FILE, write_annotation_file, write_gamestate_labels
from broadtrack_graph.io.broadcast_truth import write_broadcast_truth
from broadtrack_graph.io.cameras import camera_file_name, read_camera_file, resolve_camera_folder, write_camera_file
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic
from broadtrack_graph.io.video import open_video_writer
from broadtrack_graph.synth.broadcast import BROADCAST_PRESET, broadcast_scene, broadcast_truth_shots
from broadtrack_graph.synth.clip import clip_scene, iter_clip_frames
from broadtrack_graph.synth.clip_folder import prepare_clip_folder

logger = logging.getLogger(__name__)

CLIP_FILE = "clip.json"
PLAYER_TRUTH_FILE = "players_pitch.json"


@dataclass
class ClipWriteSummary:
    """What write_synthetic_clip produced."""

    out_dir: Path
    frames_written: int
    frames_planned: int
    seconds: float
    seconds_per_frame: float
    interrupted: bool


def read_camera_track(folder: str | Path, width_px: int, height_px: int, frame_count: int | None = None):
    """Cameras of a folder of camera_NNNNN.json files, in file order, rescaled to (width_px, height_px).

    Raises:
        InputError: the folder is missing, holds no camera file, or a file is malformed.
    """
    folder, files = resolve_camera_folder(folder)
    logger.info("rendering along the cameras in %s", folder)
    paths = [files[key] for key in sorted(files, key=lambda k: int(k))]
    if frame_count is not None:
        paths = paths[:frame_count]
    cameras = [read_camera_file(path, width_px, height_px) for path in paths]
    for path, camera in zip(paths, cameras):
        if not camera.extra_distortion.is_zero:
            raise InputError(path, "the synthetic renderer supports k1 only; this camera has other distortion terms")
    return cameras


def write_synthetic_clip(
    out_dir: str | Path,
    preset: str = "main",
    frame_count: int = 750,
    width_px: int = 1920,
    height_px: int = 1080,
    seed: int = 0,
    cameras_dir: str | Path | None = None,
    jpeg_quality: int = 90,
    write_mp4: bool = False,
    write_masks: bool = True,
    progress: bool = True,
) -> ClipWriteSummary:
    """Render a synthetic clip and write it (see the module docstring for the layout).

    Args:
        out_dir: output folder (created; an earlier synthetic clip in it is replaced whole, a file or a
            non-empty folder that is not a clip is refused: :mod:`broadtrack_graph.synth.clip_folder`).
        preset: motion / play preset (broadtrack_graph.synth.motion.PRESETS), or "broadcast" (several cameras
            and cuts: :mod:`broadtrack_graph.synth.broadcast`; not with cameras_dir).
        frame_count: frames to render (with cameras_dir: at most that many of its cameras).
        width_px, height_px: image size.
        seed: random seed; the same arguments give the same files.
        cameras_dir: render along the cameras of this folder instead of a generated track.
        jpeg_quality: JPEG quality of the frames (the clip's compression).
        write_mp4: also write OUT/clip.mp4.
        write_masks: write the per-class masks.
        progress: show a progress bar.

    Raises:
        InputError: a bad camera folder; ValueError: an unknown preset or a bad size.
    """
    out = Path(out_dir)
    cameras = None
    if cameras_dir is not None:
        cameras = read_camera_track(cameras_dir, width_px, height_px, frame_count)
        frame_count = len(cameras)
    if frame_count < 1:
        raise ValueError(f"frame_count must be >= 1, got {frame_count}")
    scene, pitch_frames, cut_frames = None, None, frozenset()
    if preset == BROADCAST_PRESET:
        if cameras is not None:
            raise ValueError("the broadcast preset generates its own cameras; give no camera folder")
        scene = broadcast_scene(frame_count, width_px, height_px, seed)
        pitch_frames, cut_frames = scene.pitch_frames, scene.cut_frames
    prepare_clip_folder(out)  # an earlier clip here is replaced whole; a file or a foreign folder is refused
    if scene is None:
        cams, tripod, lambdas, players = clip_scene(preset, frame_count, width_px, height_px, seed, cameras)
    else:
        cams, tripod, lambdas, players = scene.cameras, scene.tripods["main"], scene.lambdas_m, scene.players
    for sub in ("img1", "annotations", "cameras", "keypoints") + (("masks",) if write_masks else ()):
        (out / sub).mkdir(parents=True, exist_ok=True)
    info = {
        "preset": preset, "seed": int(seed), "width_px": int(width_px), "height_px": int(height_px), "fps": 25.0,
        "frame_count": int(frame_count), "frames_written": 0, "camera_source": str(cameras_dir) if cameras_dir else "generated",
        "jpeg_quality": int(jpeg_quality), "generator": "broadtrack_graph.synth",
    }
    write_json_atomic(out / CLIP_FILE, info, indent=2)
    if tripod is not None:
        write_json_atomic(out / "tripod.json", {"T_w": list(tripod.T_w), "delta_m": tripod.delta_m}, indent=2)
    video = None
    if write_mp4:
        try:
            video = open_video_writer(out / "clip.mp4", 25.0, (width_px, height_px))
        except InputError:
            logger.warning("cannot open an mp4v video writer; clip.mp4 is not written")
            video = None
    lines_by_frame: dict[str, dict] = {}
    boxes_by_frame: dict[str, list] = {}
    feet_by_frame: dict[str, dict] = {}
    truth_frames = []
    started = time.perf_counter()
    interrupted = False
    frames = iter_clip_frames(cams, width_px, height_px, seed, players, want_masks=write_masks, cut_frames=cut_frames)
    try:
        for frame in tqdm(frames, total=frame_count, desc="synth", unit="frame", disable=not progress):
            fid = frame.frame_id
            on_pitch = pitch_frames is None or bool(pitch_frames[frame.index])  # no truth camera on close-ups, crowd
            lines = frame.lines_norm if on_pitch else {}
            if not cv2.imwrite(str(out / "img1" / f"{fid}.jpg"), frame.image, [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)]):
                raise InputError(out / "img1" / f"{fid}.jpg", "cannot write image")
            if video is not None:
                video.write(frame.image)
            if lines:  # a frame showing no marking has no line annotation (as in SoccerNet)
                write_annotation_file(out / "annotations" / f"{fid}.json", lines)
            if on_pitch:
                write_camera_file(out / "cameras" / camera_file_name(fid), frame.camera, width_px, height_px)
                write_json_atomic(out / "keypoints" / f"{fid}.json",
                                  {name: [float(v) for v in uv] for name, uv in frame.keypoints_px.items()})
            if write_masks and frame.mask is not None and on_pitch:
                cv2.imwrite(str(out / "masks" / f"{fid}.png"), frame.mask, [cv2.IMWRITE_PNG_COMPRESSION, 1])
            lines_by_frame[fid] = lines or None
            boxes_by_frame[fid] = [[int(b[0]), *(round(float(v), 2) for v in b[1:])] for b in frame.player_boxes_px]
            feet_by_frame[fid] = {int(b[0]): players.positions_w[frame.index, int(b[0])] for b in frame.player_boxes_px}
            entry = {
                "frame_id": fid,
                "lambda_m": None if lambdas is None or not on_pitch else float(lambdas[frame.index]),
                "annotated": bool(lines),
                "occluded_classes": frame.occluded_classes if on_pitch else [],
                "folded_classes": frame.folded_classes if on_pitch else [],
            }
            if scene is not None:
                entry.update(camera_id=scene.camera_ids[frame.index], shot_kind=scene.kinds[frame.index])
            truth_frames.append(entry)
    except KeyboardInterrupt:
        interrupted = True
        logger.warning("interrupted after %d frames; writing the clip files for them", len(truth_frames))
    finally:
        if video is not None:
            video.release()
        _write_clip_files(out, info, lines_by_frame, boxes_by_frame, feet_by_frame, players.teams, truth_frames,
                          width_px, height_px, tripod)
        write_player_truth(out, players, [f["frame_id"] for f in truth_frames], info["fps"])
        if scene is not None:
            write_broadcast_truth(out, broadcast_truth_shots(scene), scene.tripods, scene.camera_ids)
    elapsed = time.perf_counter() - started
    if interrupted:
        raise KeyboardInterrupt
    written = len(truth_frames)
    return ClipWriteSummary(out, written, frame_count, elapsed, elapsed / max(written, 1), interrupted)


def _write_clip_files(out: Path, info: dict, lines_by_frame, boxes_by_frame, feet_by_frame, teams, truth_frames,
                      width_px, height_px, tripod) -> None:
    objects = []
    for index, (fid, boxes) in enumerate(boxes_by_frame.items(), start=1):
        for box in boxes:
            player, x0, y0, x1, y1 = box
            team = int(teams[player])
            foot = feet_by_frame[fid][player]
            role = {2: "referee", 3: "goalkeeper"}.get(team, "player")
            side = None if team == 2 else ("left" if (foot[0] < 0 if team == 3 else team == 0) else "right")
            objects.append({
                "id": f"player-{index}-{player}", "image_id": str(index), "track_id": int(player) + 1,
                "supercategory": "object", "category_id": {"player": 1, "goalkeeper": 2, "referee": 3}[role],
                "attributes": {"role": role, "team": side},
                "bbox_image": {"x": x0, "y": y0, "x_center": round((x0 + x1) / 2, 2), "y_center": round((y0 + y1) / 2, 2),
                               "w": round(x1 - x0, 2), "h": round(y1 - y0, 2)},
                "bbox_pitch": {"x_bottom_middle": round(float(foot[0]), 3), "y_bottom_middle": round(float(foot[1]), 3)},
            })
    if lines_by_frame:
        write_gamestate_labels(out / GAMESTATE_FILE, lines_by_frame, width_px, height_px, ".jpg",
                               sequence_name=f"synthetic-{info['preset']}-{info['seed']}", extra_annotations=objects)
    write_json_atomic(out / "players.json", boxes_by_frame)
    write_json_atomic(out / "ground_truth.json", {
        "tripod": None if tripod is None else {"T_w": list(tripod.T_w), "delta_m": tripod.delta_m},
        "frames": truth_frames,
    })
    info = dict(info, frames_written=len(truth_frames))
    write_json_atomic(out / CLIP_FILE, info, indent=2)


def write_player_truth(out_dir: str | Path, players, frame_ids: list[str], fps: float) -> None:
    """Write ``players_pitch.json``: every player's true foot position per frame (see the module docstring).

    Args:
        out_dir: the clip folder.
        players: the clip's :class:`~broadtrack_graph.synth.scene.PlayerTrack` (positions_w (F, P, 3) metres).
        frame_ids: ids of the frames written, in order (frame k is row k of positions_w).
        fps: frame rate.
    """
    teams = [int(t) for t in players.teams]
    roles = [{2: "referee", 3: "goalkeeper"}.get(t, "player") for t in teams]
    frames = {}
    for index, fid in enumerate(frame_ids):
        xy = players.positions_w[index, :, :2]
        frames[fid] = {str(p + 1): [round(float(xy[p, 0]), 4), round(float(xy[p, 1]), 4)] for p in range(len(teams))}
    write_json_atomic(Path(out_dir) / PLAYER_TRUTH_FILE, {
        "fps": float(fps), "track_ids": [p + 1 for p in range(len(teams))], "roles": roles, "teams": teams,
        "frames": frames,
    })


def read_clip_info(folder: str | Path) -> dict:
    """clip.json of a synthetic clip folder (InputError when missing or malformed)."""
    data = read_json(Path(folder) / CLIP_FILE)
    if not isinstance(data, dict) or "width_px" not in data or "height_px" not in data:
        raise InputError(Path(folder) / CLIP_FILE, "not a synthetic clip description (no width_px / height_px)")
    return data


def read_keypoints_file(path: str | Path) -> dict[str, np.ndarray]:
    """keypoints/NNNNNN.json -> {name: (2,) pixels}."""
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(path, "expected an object of keypoint name -> [u, v]")
    try:
        return {str(k): np.asarray(v, dtype=float).reshape(2) for k, v in data.items()}
    except (TypeError, ValueError):
        raise InputError(path, "a keypoint is not [u, v]") from None
