"""Players on the bird's-eye view: dots coloured by team (or by track id), with the camera footprint.

:func:`draw_players` adds players to a bird's-eye drawing
(:func:`broadtrack_graph.products.birdseye.draw_birdseye`); :func:`write_players_birdseye`
writes a whole run as an mp4 (one frame per record of the run).
"""

from __future__ import annotations

import logging
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.io.video import open_video_writer
from broadtrack_graph.products.birdseye import BirdseyeView, draw_birdseye

log = logging.getLogger(__name__)

TEAM_BGR = {"left": (230, 120, 30), "right": (40, 40, 220)}
ROLE_BGR = {"referee": (20, 20, 20), "goalkeeper": (0, 200, 255)}


def player_colour_bgr(track_id: int, team: str | None = None, role: str | None = None) -> tuple[int, int, int]:
    """Colour of a player: the role's (referee, goalkeeper), else the team's, else one per track id."""
    if role in ROLE_BGR:
        return ROLE_BGR[role]
    if team in TEAM_BGR:
        return TEAM_BGR[team]
    hue = (int(track_id) * 47) % 180 if track_id >= 0 else 0
    hsv = np.uint8([[[hue, 200 if track_id >= 0 else 0, 250]]])
    return tuple(int(v) for v in cv2.cvtColor(hsv, cv2.COLOR_HSV2BGR)[0, 0])


def draw_players(canvas_bgr: np.ndarray, view: BirdseyeView, xy_m: np.ndarray, track_ids, teams=None, roles=None,
                 std_m: np.ndarray | None = None, labels: bool = True) -> np.ndarray:
    """Draw players (in place; also returned).

    Args:
        canvas_bgr: a bird's-eye drawing made with ``view``.
        xy_m: (N, 2) positions, metres (rows with NaN are not drawn).
        track_ids: (N,) ids (-1 unknown); teams, roles: N strings or None.
        std_m: (N, 2) standard deviations, drawn as an ellipse when larger than the dot.
        labels: write the track id next to the dot.
    """
    xy_m = np.asarray(xy_m, dtype=float).reshape(-1, 2)
    n = len(xy_m)
    teams = teams if teams is not None else [None] * n
    roles = roles if roles is not None else [None] * n
    radius = max(3, int(round(view.pixels_per_m * 0.9)))
    px = view.to_px(xy_m)
    for i in np.flatnonzero(np.isfinite(xy_m).all(axis=1)):
        centre = tuple(int(v) for v in np.round(px[i]))
        colour = player_colour_bgr(int(track_ids[i]), teams[i], roles[i])
        if std_m is not None and np.isfinite(std_m[i]).all():
            axes = tuple(int(round(v * view.pixels_per_m * 2)) for v in std_m[i])  # 2 sigma
            if max(axes) > radius:
                cv2.ellipse(canvas_bgr, centre, axes, 0, 0, 360, colour, 1, cv2.LINE_AA)
        cv2.circle(canvas_bgr, centre, radius, colour, -1, cv2.LINE_AA)
        if radius >= 5:
            cv2.circle(canvas_bgr, centre, radius, (255, 255, 255), 1, cv2.LINE_AA)
        if labels and track_ids[i] >= 0:
            cv2.putText(canvas_bgr, str(int(track_ids[i])), (centre[0] + radius + 1, centre[1] - radius),
                        cv2.FONT_HERSHEY_SIMPLEX, 0.35, (255, 255, 255), 1, cv2.LINE_AA)
    return canvas_bgr


def players_birdseye_frame(camera, view: BirdseyeView, positions, rows: np.ndarray) -> np.ndarray:
    """One bird's-eye picture: the camera footprint and the players of ``rows`` of a PlayerPositions."""
    canvas = draw_birdseye(camera, view)
    return draw_players(canvas, view, positions.xy_m[rows], positions.track_id[rows],
                        [positions.teams[i] for i in rows], [positions.roles[i] for i in rows], positions.std_m[rows])


def write_players_birdseye(track, positions, out_path: str | Path, fps: float = 25.0, width_px: int = 960,
                           progress: bool = True) -> int:
    """Write an mp4 of the run from above: footprint and players per record; returns the frames written.

    Args:
        track: the run (:class:`~broadtrack_graph.types.track_record.RunRecords`).
        positions: :class:`~broadtrack_graph.io.players_file.PlayerPositions` of the run.
        out_path: the .mp4 file.

    Raises:
        InputError: the video cannot be written.
    """
    from tqdm import tqdm

    cams = np.array([r.camera.position_m for r in track.records if r.camera is not None]).reshape(-1, 3)
    view = BirdseyeView.fitting(width_px, camera_positions_w=np.median(cams, axis=0)[None] if len(cams) else None)
    size = view.size_px
    size = (size[0] - size[0] % 2, size[1] - size[1] % 2)
    out_path = Path(out_path)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    writer = open_video_writer(out_path, fps, size)
    rows_of = {}
    for i, frame in enumerate(positions.frame):
        rows_of.setdefault(int(frame), []).append(i)
    written = 0
    try:
        for record in tqdm(track.records, desc="bird's-eye", unit="frame", disable=not progress):
            rows = np.array(rows_of.get(record.frame_index, []), dtype=int)
            image = players_birdseye_frame(record.camera, view, positions, rows)
            cv2.putText(image, f"frame {record.frame_id}", (8, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1,
                        cv2.LINE_AA)
            writer.write(np.ascontiguousarray(image[:size[1], :size[0]]))
            written += 1
    finally:
        writer.release()
    return written
