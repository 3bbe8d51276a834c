"""The maps the confidence derives once per frame: the field inside its edge band, the marking map's long pieces."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.reinit.frame_maps import inside_field_edge, long_pieces

W, H = 960, 540


def test_the_band_runs_along_the_outline_not_round_the_holes_of_players():
    field = np.zeros((H, W), bool)
    field[200:, :] = True
    field[300:340, 400:412] = False  # a player's hole in the grass
    inside = inside_field_edge(field, 5)
    assert not inside[200:205].any() and inside[206:].any()  # the outer edge's band (not the image's border)
    assert inside[300:340, 394:400].all() and inside[300:340, 412:418].all()  # right beside the hole
    assert not inside[300:340, 400:412].any()  # the hole itself is not field
    assert inside[H - 1].all() and inside[250:, 0].all()  # the image's border is not an edge
    assert inside_field_edge(field, 5) is inside  # the same map asked again: made once
    assert inside_field_edge(field, 0) is field


def test_long_pieces_keep_lines_and_their_broken_stretches_and_drop_specks():
    marks = np.zeros((H, W), bool)
    marks[100, 50:400] = True  # a line
    for start in range(50, 400, 20):
        marks[200, start:start + 13] = True  # a line broken into pieces 13 px long
    rows = np.arange(300, 330)
    marks[rows, 500 + (rows - 300) // 2] = True  # a steep piece 30 px tall, 15 px wide: its longer side counts
    for k in range(40):
        marks[400 + (k % 5) * 20, 20 + 20 * k:26 + 20 * k] = True  # specks 6 px long
    marks[450, 700] = True  # a single pixel
    pieces = long_pieces(marks, 12.0)
    assert pieces[100, 50:400].all() and pieces[200].sum() == marks[200].sum()
    assert pieces[300:330].sum() == 30
    assert not pieces[400:500].any()
    assert not (pieces & ~marks).any()
    assert long_pieces(marks, 12.0) is pieces  # the same map asked again: made once
    assert long_pieces(marks, 0.0) is marks
    assert long_pieces(marks, 14.0)[200].sum() == 0  # pieces of 13 px under 14
