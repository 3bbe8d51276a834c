"""The ``broadcast`` synthetic scene: hard cuts between several tripod cameras and views with no pitch to fit.

A broadcast is a sequence of shots. The default plan (:data:`DEFAULT_PLAN`, 1500 frames at
25 fps, scaled to the requested length by :func:`broadcast_plan`)::

    main 210 | close-up 90 | main 150 | high-behind 180 | main 120 | low-16m 150 |
    crowd 60 | close-up 75 | main 165 | high-behind 120 (returns) | main 180

Pitch cameras (truth kind "main" for the main camera, "other-camera" for the others):

* ``main``: the ``main`` preset (halfway line, 55 m back, 12 m up);
* ``high-behind``: the ``high-behind`` preset (behind the left goal, 24 m up);
* ``low-16m``: the ``low-16m`` preset (on the right 16.5 m line extension, 8 m behind the
  touchline, 7 m up; where the numbers come from: :data:`~broadtrack_graph.synth.motion.PRESETS`).

Each pitch camera keeps its own tripod (T, delta) for the whole clip, and its whole-length
track is generated once (:func:`~broadtrack_graph.synth.motion.generate_camera_track`, the
preset's own random stream): a shot takes its frames from it, so a camera that returns
after a cut is where its operator would have taken it meanwhile.

Views with no camera to fit:

* close-up: a hand-held camera 3 m up, 5 m from a player on his near-touchline side (the
  main camera's play drives the players; the player is one of the three nearest the
  pitch's long axis y = 0 at the shot's start, away from the goals, so the pitch is behind him), looking
  down at his hips with a 36 deg lens: the body, head to feet, fills ~75 % of the image
  height, grass all round it;
* crowd: a pitch-side camera 3 m up near the near touchline looking 4 deg up into the near
  stand (boards at the bottom, little or no grass), panning slowly along it.

The players of a frame are those of its pitch camera's play (the main camera's for
close-ups and crowd shots); all cameras' players share count, heights and teams. No I/O
here (the clip writer writes the truth through :mod:`broadtrack_graph.io.broadcast_truth`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.synth.motion import generate_camera_track, hfov_to_focal_px, smooth_noise
from broadtrack_graph.synth.scene import PlayerTrack, simulate_players
from broadtrack_graph.types.shot import Shot

BROADCAST_PRESET = "broadcast"
"""Name of the scene on the command line (``synth --preset broadcast``)."""

KIND_MAIN = "main"
KIND_OTHER_CAMERA = "other-camera"
KIND_CLOSE_UP = "close-up"
KIND_CROWD = "crowd"
SHOT_KINDS = (KIND_MAIN, KIND_OTHER_CAMERA, KIND_CLOSE_UP, KIND_CROWD)
"""Truth kinds of a shot (the tracker's shots.json kinds)."""
PITCH_KINDS = (KIND_MAIN, KIND_OTHER_CAMERA)
"""Kinds with a pitch camera to fit."""

CAMERA_PRESETS = {"main": "main", "high-behind": "high-behind", "low-16m": "low-16m"}
"""Pitch camera id -> the motion preset that places and operates it."""

DEFAULT_PLAN: tuple[tuple[str, int], ...] = (
    ("main", 210), (KIND_CLOSE_UP, 90), ("main", 150), ("high-behind", 180), ("main", 120), ("low-16m", 150),
    (KIND_CROWD, 60), (KIND_CLOSE_UP, 75), ("main", 165), ("high-behind", 120), ("main", 180),
)
"""(camera id or no-pitch kind, frames at the full 1500-frame length), in broadcast order."""

BROADCAST_STREAM = 100
"""Random stream of the close-up and crowd cameras (presets use 0 .. len(PRESET_STREAMS) - 1)."""

PLAYER_COUNT = 22  # players and officials of every camera's play (main camera's count)
PLAYER_SPREAD_M = 22.0  # their spread around play (main camera's)
CLOSE_UP_HEIGHT_M = 3.0  # close-up camera height above the pitch (held high, looking down: grass behind)
CLOSE_UP_DISTANCE_M = 5.0  # its horizontal distance to the player (along +y, the near touchline side)
CLOSE_UP_AIM_HEIGHT_M = 0.95  # it aims at this height on the player (hips): head and feet in view
CLOSE_UP_HFOV_DEG = 36.0  # its horizontal field of view (the 1.8 m body spans ~75 % of the image height)
CROWD_POSITION_W = (0.0, 30.0, -3.0)  # crowd camera: pitch side, near touchline, 3 m up (metres)
CROWD_TILT_DEG = 94.0  # 4 deg above horizontal: boards at the bottom, the near stand above
CROWD_HFOV_DEG = 30.0
CROWD_PAN_SWEEP_DEG = 25.0  # it pans slowly along the stand over +- this


@dataclass(frozen=True)
class PlannedShot:
    """One shot of the plan.

    start, end: first frame index and one past the last (0-based).
    kind: one of :data:`SHOT_KINDS`.
    camera_id: the pitch camera ("main", "high-behind", "low-16m"), None for close-up / crowd.
    """

    start: int
    end: int
    kind: str
    camera_id: str | None

    @property
    def frames(self) -> int:
        return self.end - self.start


def broadcast_plan(frame_count: int, plan=DEFAULT_PLAN) -> list[PlannedShot]:
    """The plan scaled to ``frame_count`` frames, shot lengths in proportion.

    Every shot keeps at least 5 frames when ``frame_count >= 5 * len(plan)``, else at least 2.

    Raises:
        ValueError: fewer than 2 frames per shot of the plan.
    """
    count = len(plan)
    if frame_count < 2 * count:
        raise ValueError(f"the broadcast plan has {count} shots: give at least {2 * count} frames, got {frame_count}")
    least = 5 if frame_count >= 5 * count else 2
    weights = np.array([frames for _, frames in plan], dtype=float)
    raw = weights * frame_count / weights.sum()
    lengths = np.maximum(np.floor(raw).astype(int), least)
    while lengths.sum() > frame_count:  # take frames from the longest shots that can spare one
        spare = np.where(lengths > least, lengths, -1)
        lengths[int(np.argmax(spare))] -= 1
    while lengths.sum() < frame_count:  # give frames to the shots furthest below their share
        lengths[int(np.argmax(raw - lengths))] += 1
    shots, start = [], 0
    for (source, _), length in zip(plan, lengths):
        if source in CAMERA_PRESETS:
            kind = KIND_MAIN if source == "main" else KIND_OTHER_CAMERA
            shots.append(PlannedShot(start, start + int(length), kind, source))
        elif source in (KIND_CLOSE_UP, KIND_CROWD):
            shots.append(PlannedShot(start, start + int(length), source, None))
        else:
            raise ValueError(f"unknown plan entry '{source}'; use a camera id {sorted(CAMERA_PRESETS)} or "
                             f"'{KIND_CLOSE_UP}' / '{KIND_CROWD}'")
        start += int(length)
    return shots


@dataclass
class BroadcastScene:
    """Everything the clip writer renders and writes for a broadcast clip.

    cameras: one Camera per frame at (width_px, height_px) (pitch camera, close-up or crowd camera).
    shots: the plan.
    camera_ids: (F,) pitch camera id per frame, None on close-up / crowd frames.
    kinds: (F,) shot kind per frame.
    tripods: pitch camera id -> its tripod (the same for all its shots).
    lambdas_m: (F,) lambda of pitch frames (metres), NaN on the others.
    players: the players drawn in each frame.
    """

    cameras: list[Camera]
    shots: list[PlannedShot]
    camera_ids: list[str | None]
    kinds: list[str]
    tripods: dict[str, Tripod]
    lambdas_m: np.ndarray
    players: PlayerTrack

    @property
    def pitch_frames(self) -> np.ndarray:
        """(F,) bool: frames with a pitch camera to fit."""
        return np.array([c is not None for c in self.camera_ids])

    @property
    def cut_frames(self) -> frozenset[int]:
        """First frames of the shots after the first (hard cuts)."""
        return frozenset(s.start for s in self.shots[1:])


def close_up_cameras(subject_w: np.ndarray, width_px: int, height_px: int, seed: int) -> list[Camera]:
    """Hand-held close-up cameras following a player.

    Args:
        subject_w: (N, 3) the player's foot positions (metres, pitch frame).
        width_px, height_px: image size.
        seed: seed of the operator's wobble.

    Returns:
        N cameras CLOSE_UP_DISTANCE_M from the player on his +y side (at most y = 36 m, inside the
        boards), CLOSE_UP_HEIGHT_M up, aimed at CLOSE_UP_AIM_HEIGHT_M on him, with a 0.3 deg wobble.
    """
    count = len(subject_w)
    C_w = np.column_stack([subject_w[:, 0], np.minimum(subject_w[:, 1] + CLOSE_UP_DISTANCE_M, 36.0),
                           np.full(count, -CLOSE_UP_HEIGHT_M)])
    aim_w = subject_w + np.array([0.0, 0.0, -CLOSE_UP_AIM_HEIGHT_M])
    direction = aim_w - C_w
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    wobble = np.radians(0.3) * smooth_noise((int(seed), BROADCAST_STREAM, 1), count, 2, 12.0)
    tilt_rad = np.arccos(np.clip(direction[:, 2], -1.0, 1.0)) + wobble[:, 1]
    pan_rad = np.arctan2(direction[:, 0], -direction[:, 1]) + wobble[:, 0]
    focal_px = float(hfov_to_focal_px(math.radians(CLOSE_UP_HFOV_DEG), width_px))
    return [Camera(focal_px, 0.01, float(pan_rad[i]), float(tilt_rad[i]), 0.0, C_w[i], width_px, height_px)
            for i in range(count)]


def crowd_cameras(count: int, width_px: int, height_px: int, seed: int) -> list[Camera]:
    """(count) pitch-side cameras looking into the near stand (pan 180 deg: towards +y), panning slowly."""
    sweep = np.radians(CROWD_PAN_SWEEP_DEG) * np.tanh(smooth_noise((int(seed), BROADCAST_STREAM, 2), count, 1, 40.0)[:, 0])
    tilt_rad = math.radians(CROWD_TILT_DEG)
    focal_px = float(hfov_to_focal_px(math.radians(CROWD_HFOV_DEG), width_px))
    C_w = np.asarray(CROWD_POSITION_W, dtype=float)
    return [Camera(focal_px, 0.01, math.pi + float(sweep[i]), tilt_rad, 0.0, C_w, width_px, height_px)
            for i in range(count)]


def broadcast_scene(frame_count: int, width_px: int, height_px: int, seed: int = 0, plan=DEFAULT_PLAN
                    ) -> BroadcastScene:
    """Cameras, truth and players of a broadcast clip (module docstring); the same arguments, the same scene.

    Raises:
        ValueError: too few frames for the plan (:func:`broadcast_plan`).
    """
    shots = broadcast_plan(frame_count, plan)
    used = sorted({s.camera_id for s in shots if s.camera_id is not None} | {"main"}, key=list(CAMERA_PRESETS).index)
    tracks = {cid: generate_camera_track(CAMERA_PRESETS[cid], frame_count, width_px, height_px, seed) for cid in used}
    plays = {cid: simulate_players(track.ball_w, PLAYER_COUNT, PLAYER_SPREAD_M, seed) for cid, track in tracks.items()}
    source = np.array(["main" if s.camera_id is None else s.camera_id for s in shots for _ in range(s.frames)])
    positions = np.empty_like(plays["main"].positions_w)
    phases = np.empty_like(plays["main"].phases)
    for cid, play in plays.items():
        rows = source == cid
        positions[rows] = play.positions_w[rows]
        phases[rows] = play.phases[rows]
    main_play = plays["main"]
    players = PlayerTrack(positions, main_play.heights_m, main_play.teams, phases)
    outfield = np.flatnonzero(main_play.teams < 2)
    cameras: list[Camera] = []
    camera_ids: list[str | None] = []
    kinds: list[str] = []
    lambdas = np.full(frame_count, np.nan)
    for number, shot in enumerate(shots):
        rows = slice(shot.start, shot.end)
        if shot.camera_id is not None:
            cameras += tracks[shot.camera_id].cameras[rows]
            lambdas[rows] = tracks[shot.camera_id].lambdas_m[rows]
        elif shot.kind == KIND_CLOSE_UP:
            xy = positions[shot.start, outfield, :2]
            away = np.abs(xy[:, 1]) + 10.0 * np.maximum(np.abs(xy[:, 0]) - 38.0, 0.0)  # off y = 0, or near a goal
            nearest = outfield[np.argsort(away, kind="stable")]
            subject = int(nearest[(int(seed) + number) % min(3, len(nearest))])
            cameras += close_up_cameras(positions[rows, subject], width_px, height_px, seed)
        else:
            cameras += crowd_cameras(shot.frames, width_px, height_px, seed)
        camera_ids += [shot.camera_id] * shot.frames
        kinds += [shot.kind] * shot.frames
    tripods = {cid: tracks[cid].tripod for cid in used if any(s.camera_id == cid for s in shots)}
    return BroadcastScene(cameras, shots, camera_ids, kinds, tripods, lambdas, players)



def broadcast_truth_shots(scene: BroadcastScene) -> list[Shot]:
    """The plan as the tracker's Shot records (boundary "start" then "hard"; views: frames per view kind)."""
    view = {KIND_MAIN: "main", KIND_OTHER_CAMERA: "main", KIND_CLOSE_UP: KIND_CLOSE_UP, KIND_CROWD: KIND_CROWD}
    return [Shot(s.start, s.end, s.kind, s.camera_id, "start" if i == 0 else "hard", {view[s.kind]: s.frames})
            for i, s in enumerate(scene.shots)]
