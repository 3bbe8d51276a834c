import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.players_file import positions_from_lines
from broadtrack_graph.products.birdseye import BirdseyeView, draw_birdseye
from broadtrack_graph.products.overlay import render_overlay_frame
from broadtrack_graph.products.players_view import TEAM_BGR, draw_players, player_colour_bgr


def test_players_are_drawn_in_team_colours_at_their_positions():
    view = BirdseyeView.fitting(600)
    canvas = draw_birdseye(None, view)
    draw_players(canvas, view, np.array([[10.0, 5.0], [np.nan, 0.0]]), np.array([3, 4]), ["left", None], [None, None])
    u, v = np.round(view.to_px(np.array([10.0, 5.0]))[0]).astype(int)
    assert tuple(int(c) for c in canvas[v, u]) == TEAM_BGR["left"]
    assert player_colour_bgr(5, None, "referee") != player_colour_bgr(5, "left", None)


def test_overlay_inset_with_players():
    camera = Camera.from_degrees(1100.0, 0.0, 0.0, 72.0, 0.0, [0.0, 55.0, -15.0], 960, 540)
    positions = positions_from_lines([{"frame": 0, "frame_id": "000001", "track_id": 1, "box_px": [1, 2, 3, 4],
                                       "x_m": 0.0, "y_m": 0.0, "std_m": [0.1, 0.1], "team": "right"}])
    view = BirdseyeView.fitting(480, camera_positions_w=camera.position_m[None])
    image = np.zeros((540, 960, 3), np.uint8)

    without = render_overlay_frame(image, None, view, True)
    with_players = render_overlay_frame(image, None, view, True, players=(positions, np.array([0])))
    assert np.abs(with_players.astype(int) - without.astype(int)).sum() > 0
