"""The synthetic cameras: where each preset's broadcast camera stands and how it is operated.

One :class:`MotionPreset` per kind of camera a broadcast shows (the main camera, a camera on the
16 m line, high behind a goal, a lower-league gantry, ...); :mod:`broadtrack_graph.synth.motion`
turns a preset into a camera track. Angles in degrees, distances in metres (SoccerNet pitch frame,
z down), times in seconds. No I/O here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class MotionPreset:
    """How one broadcast camera is placed and operated.

    All angles in degrees, distances in metres (pitch frame, z down), times in seconds.
    """

    name: str
    tripod_T_w: tuple[float, float, float]  # pan/tilt axes meeting point
    delta_m: float  # distance of the optical axis from T
    ball_x_range_m: tuple[float, float]  # where play happens for this camera (x)
    ball_y_range_m: tuple[float, float]  # where play happens (y)
    hfov_range_deg: tuple[float, float]  # tightest and widest horizontal field of view
    hfov_typical_deg: float  # field of view the operator returns to
    dribble_speed_mps: tuple[float, float]  # ball speed range while dribbling
    pass_speed_mps: tuple[float, float]  # ball speed range of long passes (sweeps)
    pass_probability: float  # chance that the next play event is a long pass
    pause_probability: float  # chance that the next play event is a pause
    follow_time_s: float  # time constant of the fluid head following the aim point
    zoom_time_s: float  # time constant of zoom changes
    sparse_zoom_per_min: float  # zoom-ins on a sparse area per minute of play
    sparse_zoom_hfov_deg: tuple[float, float]  # field of view during those zoom-ins
    sparse_zoom_duration_s: tuple[float, float]  # how long they last
    aim_offset_y_m: float  # operator aims this far from the ball along y (framing)
    aim_x_range_m: tuple[float, float]  # the aim point stays within this x range (keeps grass in view)
    aim_y_range_m: tuple[float, float]  # the aim point stays within this y range
    jitter_deg: float  # RMS of the operator's small pan/tilt jitter
    roll_max_deg: float  # |constant roll| <= this
    lambda_wide_m: float  # lambda at the widest zoom
    lambda_tele_m: float  # lambda at the tightest zoom
    k1_wide: float  # k1 at the widest zoom
    k1_tele: float  # k1 at the tightest zoom
    player_count: int  # players on the pitch (for the renderer)
    player_spread_m: float  # how tightly players cluster around the ball (renderer)
    # The operator opens the zoom ahead of a sweep so that the view turns by at most this many horizontal
    # fields of view per second (a whip pan is shot wide, a tight view only drifts); None: no such limit.
    max_view_speed_fov_per_s: float | None = None


PRESETS: dict[str, MotionPreset] = {
    "main": MotionPreset(
        name="main", tripod_T_w=(0.0, 55.0, -12.0), delta_m=0.22,
        ball_x_range_m=(-48.0, 48.0), ball_y_range_m=(-28.0, 28.0),
        hfov_range_deg=(14.0, 42.0), hfov_typical_deg=30.0,
        dribble_speed_mps=(1.5, 7.0), pass_speed_mps=(12.0, 22.0), pass_probability=0.2, pause_probability=0.15,
        follow_time_s=0.55, zoom_time_s=1.2,
        sparse_zoom_per_min=1.5, sparse_zoom_hfov_deg=(12.0, 18.0), sparse_zoom_duration_s=(2.0, 4.0),
        aim_offset_y_m=3.0, aim_x_range_m=(-40.0, 40.0), aim_y_range_m=(-18.0, 22.0), jitter_deg=0.01, roll_max_deg=0.2,
        lambda_wide_m=0.05, lambda_tele_m=0.45, k1_wide=0.045, k1_tele=0.008,
        player_count=22, player_spread_m=22.0,
    ),
    "16m": MotionPreset(
        name="16m", tripod_T_w=(36.0, 48.0, -9.0), delta_m=0.2,
        ball_x_range_m=(5.0, 50.0), ball_y_range_m=(-26.0, 26.0),
        hfov_range_deg=(16.0, 50.0), hfov_typical_deg=36.0,
        dribble_speed_mps=(1.5, 7.0), pass_speed_mps=(12.0, 20.0), pass_probability=0.18, pause_probability=0.15,
        follow_time_s=0.5, zoom_time_s=1.0,
        sparse_zoom_per_min=1.0, sparse_zoom_hfov_deg=(14.0, 20.0), sparse_zoom_duration_s=(2.0, 3.5),
        aim_offset_y_m=2.0, aim_x_range_m=(0.0, 42.0), aim_y_range_m=(-20.0, 20.0), jitter_deg=0.012, roll_max_deg=0.25,
        lambda_wide_m=0.04, lambda_tele_m=0.35, k1_wide=0.055, k1_tele=0.01,
        player_count=18, player_spread_m=18.0,
    ),
    "high-behind": MotionPreset(
        name="high-behind", tripod_T_w=(-75.0, 0.0, -24.0), delta_m=0.25,
        ball_x_range_m=(-50.0, -5.0), ball_y_range_m=(-26.0, 26.0),
        hfov_range_deg=(18.0, 48.0), hfov_typical_deg=34.0,
        dribble_speed_mps=(1.5, 6.0), pass_speed_mps=(10.0, 18.0), pass_probability=0.15, pause_probability=0.2,
        follow_time_s=0.6, zoom_time_s=1.2,
        sparse_zoom_per_min=1.0, sparse_zoom_hfov_deg=(16.0, 22.0), sparse_zoom_duration_s=(2.0, 3.5),
        aim_offset_y_m=0.0, aim_x_range_m=(-44.0, -2.0), aim_y_range_m=(-24.0, 24.0), jitter_deg=0.01, roll_max_deg=0.2,
        lambda_wide_m=0.05, lambda_tele_m=0.4, k1_wide=0.05, k1_tele=0.008,
        player_count=18, player_spread_m=18.0,
    ),
    "hard": MotionPreset(
        name="hard", tripod_T_w=(0.0, 55.0, -12.0), delta_m=0.22,
        ball_x_range_m=(-50.0, 50.0), ball_y_range_m=(-30.0, 30.0),
        hfov_range_deg=(6.0, 45.0), hfov_typical_deg=24.0,
        dribble_speed_mps=(3.0, 9.0), pass_speed_mps=(22.0, 35.0), pass_probability=0.45, pause_probability=0.05,
        follow_time_s=0.22, zoom_time_s=0.5,
        sparse_zoom_per_min=6.0, sparse_zoom_hfov_deg=(6.0, 9.0), sparse_zoom_duration_s=(1.5, 3.0),
        aim_offset_y_m=3.0, aim_x_range_m=(-42.0, 42.0), aim_y_range_m=(-18.0, 22.0), jitter_deg=0.03, roll_max_deg=0.3,
        lambda_wide_m=0.05, lambda_tele_m=0.6, k1_wide=0.07, k1_tele=0.01,
        player_count=30, player_spread_m=10.0,
    ),
    # The main camera held wide (tactical views) on a lens with strong barrel distortion at wide
    # angle: the preset that needs k1 (at hfov 55 deg, k1 = 0.1 moves the image corners ~20 px).
    "wide": MotionPreset(
        name="wide", tripod_T_w=(0.0, 55.0, -12.0), delta_m=0.22,
        ball_x_range_m=(-48.0, 48.0), ball_y_range_m=(-28.0, 28.0),
        hfov_range_deg=(38.0, 62.0), hfov_typical_deg=52.0,
        dribble_speed_mps=(1.5, 7.0), pass_speed_mps=(12.0, 22.0), pass_probability=0.2, pause_probability=0.15,
        follow_time_s=0.6, zoom_time_s=1.5,
        sparse_zoom_per_min=0.0, sparse_zoom_hfov_deg=(38.0, 40.0), sparse_zoom_duration_s=(2.0, 3.0),
        aim_offset_y_m=3.0, aim_x_range_m=(-30.0, 30.0), aim_y_range_m=(-12.0, 16.0), jitter_deg=0.01, roll_max_deg=0.2,
        lambda_wide_m=0.05, lambda_tele_m=0.2, k1_wide=0.1, k1_tele=0.04,
        player_count=22, player_spread_m=22.0,
    ),
    "long": MotionPreset(
        name="long", tripod_T_w=(0.0, 55.0, -12.0), delta_m=0.22,
        ball_x_range_m=(-48.0, 48.0), ball_y_range_m=(-28.0, 28.0),
        hfov_range_deg=(14.0, 42.0), hfov_typical_deg=30.0,
        dribble_speed_mps=(1.0, 6.0), pass_speed_mps=(10.0, 20.0), pass_probability=0.15, pause_probability=0.2,
        follow_time_s=0.6, zoom_time_s=1.4,
        sparse_zoom_per_min=1.0, sparse_zoom_hfov_deg=(12.0, 18.0), sparse_zoom_duration_s=(2.0, 4.0),
        aim_offset_y_m=3.0, aim_x_range_m=(-40.0, 40.0), aim_y_range_m=(-18.0, 22.0), jitter_deg=0.01, roll_max_deg=0.2,
        lambda_wide_m=0.05, lambda_tele_m=0.45, k1_wide=0.045, k1_tele=0.008,
        player_count=22, player_spread_m=22.0,
    ),
    # A lower-league ground: the camera on a low gantry at the halfway line, 7 m behind the touchline
    # and 5.5 m up, held wider. The far half of the pitch is seen at a grazing angle (its markings a
    # pixel or two thin), so fewer markings are in view and the near ones dominate.
    "low": MotionPreset(
        name="low", tripod_T_w=(0.0, 41.0, -5.5), delta_m=0.18,
        ball_x_range_m=(-48.0, 48.0), ball_y_range_m=(-28.0, 28.0),
        hfov_range_deg=(22.0, 60.0), hfov_typical_deg=44.0,
        dribble_speed_mps=(1.5, 7.0), pass_speed_mps=(12.0, 22.0), pass_probability=0.2, pause_probability=0.15,
        follow_time_s=0.5, zoom_time_s=1.2,
        sparse_zoom_per_min=1.0, sparse_zoom_hfov_deg=(20.0, 26.0), sparse_zoom_duration_s=(2.0, 4.0),
        aim_offset_y_m=4.0, aim_x_range_m=(-38.0, 38.0), aim_y_range_m=(-14.0, 22.0), jitter_deg=0.015,
        roll_max_deg=0.3, lambda_wide_m=0.04, lambda_tele_m=0.3, k1_wide=0.06, k1_tele=0.012,
        player_count=22, player_spread_m=22.0,
    ),
    # A low camera on the extension of the right 16.5 m line (x = 52.5 - 16.5 = 36 m), as the stadium camera
    # plans of broadcasters place one on each 16 m line (e.g. UEFA's and FIFA's standard plans: main camera at
    # the halfway line high in the main stand, "16 m left / right" cameras, low ones in the first rows): here
    # 8 m behind the near touchline (y = 42 m, just inside the stands' foot at 43 m, behind the 38.5 m boards)
    # and 7 m up (a platform in the first rows). It follows play in the right half, tighter than the main
    # camera because it is closer to it.
    "low-16m": MotionPreset(
        name="low-16m", tripod_T_w=(36.0, 42.0, -7.0), delta_m=0.2,
        ball_x_range_m=(8.0, 50.0), ball_y_range_m=(-24.0, 26.0),
        hfov_range_deg=(18.0, 52.0), hfov_typical_deg=38.0,
        dribble_speed_mps=(1.5, 7.0), pass_speed_mps=(12.0, 20.0), pass_probability=0.18, pause_probability=0.15,
        follow_time_s=0.5, zoom_time_s=1.0,
        sparse_zoom_per_min=1.0, sparse_zoom_hfov_deg=(16.0, 22.0), sparse_zoom_duration_s=(2.0, 3.5),
        aim_offset_y_m=3.0, aim_x_range_m=(6.0, 44.0), aim_y_range_m=(-16.0, 22.0), jitter_deg=0.012,
        roll_max_deg=0.25, lambda_wide_m=0.04, lambda_tele_m=0.35, k1_wide=0.055, k1_tele=0.01,
        player_count=22, player_spread_m=18.0,
    ),
    # The main camera through fast play: counter-attacks and long passes swept at 40 deg/s and more (shot wide,
    # the zoom opened ahead of each sweep, so the frames are smeared by motion blur but the view moves by about a
    # field of view a second), and zoom-ins from wide down to a 5 deg field of view on a player, where a frame
    # may show a single marking or none.
    "fast": MotionPreset(
        name="fast", tripod_T_w=(0.0, 55.0, -12.0), delta_m=0.22,
        ball_x_range_m=(-50.0, 50.0), ball_y_range_m=(-30.0, 30.0),
        hfov_range_deg=(4.8, 45.0), hfov_typical_deg=22.0,
        dribble_speed_mps=(4.0, 9.0), pass_speed_mps=(25.0, 36.0), pass_probability=0.6, pause_probability=0.05,
        follow_time_s=0.22, zoom_time_s=0.35,
        sparse_zoom_per_min=8.0, sparse_zoom_hfov_deg=(4.8, 5.2), sparse_zoom_duration_s=(5.0, 7.0),
        aim_offset_y_m=3.0, aim_x_range_m=(-42.0, 42.0), aim_y_range_m=(-18.0, 22.0), jitter_deg=0.02, roll_max_deg=0.2,
        lambda_wide_m=0.05, lambda_tele_m=0.6, k1_wide=0.05, k1_tele=0.005,
        player_count=22, player_spread_m=18.0, max_view_speed_fov_per_s=1.0,
    ),
}
"""Preset name -> camera placement and operating style."""

PRESET_STREAMS = ("16m", "hard", "high-behind", "long", "main", "wide", "low", "low-16m", "fast")
"""The random stream of each preset's clips, by position: fixed, so a new preset (added at the end) changes no
existing clip."""


def get_preset(name: str) -> MotionPreset:
    """The preset called ``name``; ValueError listing the known names otherwise."""
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown preset '{name}'; choose one of {sorted(PRESETS)}") from None
