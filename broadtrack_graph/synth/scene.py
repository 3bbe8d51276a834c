"""The synthetic stadium: geometry of boards, stands, goals, and the players' motion.

Pitch frame: SoccerNet's world frame (metres, origin at the centre spot, x to the right goal,
+y to the near touchline, z DOWN). No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.synth.motion import smooth_noise


@dataclass(frozen=True)
class Stadium:
    """Where the surroundings of the pitch are (metres, pitch frame).

    The advertising boards are vertical walls on the rectangle |x| = board_half_x_m,
    |y| = board_half_y_m. The stands rise from the rectangle |x| = stand_half_x_m,
    |y| = stand_half_y_m at stand_slope_deg up to stand_top_m; above is the roof.
    The ground texture covers the stand base rectangle.
    """

    board_half_x_m: float = 57.0  # boards behind the goal lines
    board_half_y_m: float = 38.5  # boards along the touchlines
    board_height_m: float = 0.9  # height of the boards
    stand_half_x_m: float = 61.5  # foot of the stands behind the goals
    stand_half_y_m: float = 43.0  # foot of the stands along the touchlines
    stand_slope_deg: float = 33.0  # rake of the stands
    stand_top_m: float = 24.0  # height of the last row; above it the roof
    goal_depth_m: float = 2.0  # depth of the goal net behind the goal line
    goal_net_top_m: float = 2.0  # height of the back of the net
    post_radius_m: float = 0.06  # goal posts and crossbar (12 cm wide)
    line_width_m: float = 0.12  # width of the painted markings

    def air_contains(self, point_w) -> bool:
        """True when a point (3,) is above the ground and the stands (a camera must be)."""
        x, y, z = (float(v) for v in point_w)
        height = -z
        slope = math.tan(math.radians(self.stand_slope_deg))
        stand = max(abs(x) - self.stand_half_x_m, abs(y) - self.stand_half_y_m, 0.0) * slope
        return height > stand and height > 0


DEFAULT_STADIUM = Stadium()


# --------------------------------------------------------------------------- goals


@dataclass(frozen=True)
class GoalPart:
    """A straight goal tube (post or crossbar) or a net panel.

    kind: "frame" (white tube, radius_m) or "net" (a planar quad, corners_w (4, 3)).
    """

    kind: str
    points_w: np.ndarray  # frame: (2, 3) axis ends; net: (4, 3) quad corners
    radius_m: float = 0.0


def goal_parts(pitch: PitchTemplate, stadium: Stadium = DEFAULT_STADIUM) -> list[GoalPart]:
    """Posts, crossbars, back frame and net panels of both goals (metres, pitch frame)."""
    parts: list[GoalPart] = []
    d = pitch.dimensions
    half_l, post_y, bar_z = d.length_m / 2, d.goal_width_m / 2, -d.goal_height_m
    depth, back_z = stadium.goal_depth_m, -stadium.goal_net_top_m
    for side in (-1.0, 1.0):
        x0 = side * half_l
        x1 = side * (half_l + depth)
        net = [
            [(x0, -post_y, bar_z), (x0, post_y, bar_z), (x1, post_y, back_z), (x1, -post_y, back_z)],  # roof
            [(x1, -post_y, back_z), (x1, post_y, back_z), (x1, post_y, 0.0), (x1, -post_y, 0.0)],  # back
            [(x0, -post_y, bar_z), (x1, -post_y, back_z), (x1, -post_y, 0.0), (x0, -post_y, 0.0)],  # side
            [(x0, post_y, bar_z), (x1, post_y, back_z), (x1, post_y, 0.0), (x0, post_y, 0.0)],  # side
        ]
        for quad in net:
            parts.append(GoalPart("net", np.asarray(quad, dtype=float)))
        # Back frame: thin tubes along the back edges of the net.
        for a, b in (((x1, -post_y, back_z), (x1, post_y, back_z)), ((x0, -post_y, bar_z), (x1, -post_y, back_z)),
                     ((x0, post_y, bar_z), (x1, post_y, back_z))):
            parts.append(GoalPart("back", np.asarray([a, b], dtype=float), 0.025))
        for a, b in (((x0, -post_y, bar_z), (x0, post_y, bar_z)), ((x0, -post_y, bar_z), (x0, -post_y, 0.0)),
                     ((x0, post_y, bar_z), (x0, post_y, 0.0))):
            parts.append(GoalPart("frame", np.asarray([a, b], dtype=float), stadium.post_radius_m))
    return parts


# --------------------------------------------------------------------------- players


@dataclass
class PlayerTrack:
    """Players over a clip.

    positions_w: (F, P, 3) foot positions, metres, z = 0.
    heights_m: (P,) standing heights.
    teams: (P,) 0 / 1 outfield teams, 2 referee, 3 goalkeeper (player 0 left goal, player 1 right goal).
    phases: (F, P) running-cycle phase (radians) for the leg animation.
    """

    positions_w: np.ndarray
    heights_m: np.ndarray
    teams: np.ndarray
    phases: np.ndarray


def simulate_players(ball_w: np.ndarray, count: int, spread_m: float, seed: int, fps: float = 25.0) -> PlayerTrack:
    """Players who drift around the play with their own smooth random motion.

    Args:
        ball_w: (F, 3) play position per frame, metres.
        count: number of outfield players and officials on screen (>= 0).
        spread_m: typical distance of players from the play.
        seed: random seed.

    Returns:
        PlayerTrack with positions inside the pitch (|x| <= 53, |y| <= 34.5).
    """
    rng = np.random.default_rng([int(seed), 991])
    frames = len(ball_w)
    if count <= 0:
        empty = np.zeros((frames, 0, 3))
        return PlayerTrack(empty, np.zeros(0), np.zeros(0, dtype=int), np.zeros((frames, 0)))
    # Each player keeps a formation offset from the play and wanders around it (prefix-stable noise).
    offsets = rng.normal(0.0, spread_m, size=(count, 2)) * np.array([1.0, 0.7])
    wander = smooth_noise((int(seed), 993, count), frames, count * 2, 15.0).reshape(frames, count, 2)
    wander *= 2.5  # metres
    # Players follow the play with a lag.
    lagged = np.empty((frames, 2))
    state = ball_w[0, :2].copy()
    for i in range(frames):
        state += (ball_w[i, :2] - state) * (1.0 / (0.8 * fps))
        lagged[i] = state
    xy = lagged[:, None, :] + offsets[None] + wander
    teams = np.array([p % 2 for p in range(count)])
    if count >= 3:
        teams[-1] = 2  # referee
    if count >= 6:  # two goalkeepers, in front of their goals, shifting with the play
        for p, side in ((0, -1.0), (1, 1.0)):
            teams[p] = 3
            xy[:, p, 0] = side * 49.0 + 0.6 * wander[:, p, 0]
            xy[:, p, 1] = 0.15 * lagged[:, 1] + 0.6 * wander[:, p, 1]
    xy[..., 0] = np.clip(xy[..., 0], -53.0, 53.0)
    xy[..., 1] = np.clip(xy[..., 1], -34.5, 34.5)
    positions = np.concatenate([xy, np.zeros((frames, count, 1))], axis=2)
    heights = rng.uniform(1.72, 1.92, size=count)
    speeds = np.linalg.norm(np.diff(xy, axis=0, prepend=xy[:1]), axis=2) * fps
    phases = np.cumsum(speeds * (2 * math.pi / 2.2) / fps, axis=0) + rng.uniform(0, 2 * math.pi, count)
    return PlayerTrack(positions, heights, teams, phases)
