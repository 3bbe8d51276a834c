"""The image's straight markings split into the pitch's two directions (court model)."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.reinit.court_families import line_families
from reinit_helpers import BOX_SEGMENTS, box_view, image_lines

W, H = 1280, 720


def test_line_families_split_the_lines_by_direction():
    lines = image_lines(box_view(), BOX_SEGMENTS)
    splits = line_families(lines, (W, H))
    assert splits
    family = splits[0].family
    assert len(set(family[:3])) == 1 and len(set(family[3:])) == 1 and family[0] != family[3] and -1 not in family


def test_too_few_lines_give_no_split():
    lines = image_lines(box_view(), BOX_SEGMENTS[:3])  # one direction only
    assert all(min(np.sum(s.family == 0), np.sum(s.family == 1)) >= 2 for s in line_families(lines, (W, H)))
    assert line_families(lines[:1], (W, H)) == []
