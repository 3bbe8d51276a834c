"""The association of a fit's points (broadtrack_graph.reinit.linefit_pairs): the segments within reach give the
same nearest segment, foot and distance to the bit as every pair does, or say they cannot."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.template import to_segments
from broadtrack_graph.reinit.linefit_pairs import FitLayout, NearestSegments, PointSegmentPairs


def _every_pair(points, layout, uv, usable):
    """(segment, t, distance) of each point by every pair (the reference): blocked segments at inf."""
    pairs = PointSegmentPairs(layout)
    a, d = uv[:-1][pairs.segment], (uv[1:] - uv[:-1])[pairs.segment]
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-12)
    t, dist2 = to_segments(points[pairs.point, 0], points[pairs.point, 1], a[:, 0], a[:, 1], d[:, 0], d[:, 1], length2)
    dist2[~usable[pairs.segment]] = np.inf
    nearest = pairs.first_minimum(dist2)
    return pairs.segment[nearest], t[nearest], np.sqrt(dist2[nearest])


def _frame(seed):
    """A fit's layout: polylines of a few classes (one doubling back on itself and one with repeated samples: ties),
    points near them, some segments not usable."""
    rng = np.random.default_rng(seed)
    samples = [int(n) for n in rng.integers(3, 30, 5)]
    polylines = [np.cumsum(rng.normal(0, 15, (n, 2)), axis=0) + rng.uniform(100, 900, 2) for n in samples]
    polylines[0][samples[0] // 2:] = polylines[0][:samples[0] - samples[0] // 2][::-1]  # back along itself
    polylines[1][1:4] = polylines[1][1]  # zero-length segments
    counts = [int(n) for n in rng.integers(3, 40, 5)]
    points = []
    for poly, m in zip(polylines, counts):
        pick = rng.integers(0, len(poly) - 1, m)
        t = rng.uniform(0, 1, (m, 1))
        points.append(poly[pick] + t * (poly[pick + 1] - poly[pick]) + rng.normal(0, 4, (m, 2)))
    points[2][:3] = polylines[2][:3]  # exactly on samples
    layout = FitLayout(counts, samples)
    usable = layout.joins_next & (rng.uniform(size=len(layout.joins_next)) > 0.1)
    usable[layout.class_segment_start] = layout.joins_next[layout.class_segment_start]  # each class seen
    return np.vstack(points), layout, np.vstack(polylines), usable


@pytest.mark.parametrize("seed", range(6))
def test_the_segments_within_reach_give_every_pair_s_answer_to_the_bit(seed):
    points, layout, uv, usable = _frame(seed)
    got = NearestSegments(points, layout, 60.0).within_reach(uv, usable)
    assert got is not None
    for a, b in zip(got, _every_pair(points, layout, uv, usable)):
        np.testing.assert_array_equal(a, b)


def test_a_point_out_of_reach_is_not_answered():
    points, layout, uv, usable = _frame(0)
    far = points.copy()
    far[0] += 500.0
    assert NearestSegments(far, layout, 60.0).within_reach(uv, usable) is None
    # the reach is kept a pixel short: a point 59.5 px from its class's only segment is not answered either
    layout = FitLayout([1], [2])
    line = np.array([[0.0, 0.0], [100.0, 0.0]])
    assert NearestSegments(np.array([[50.0, 59.5]]), layout, 60.0).within_reach(line, np.ones(1, bool)) is None
    assert NearestSegments(np.array([[50.0, 58.5]]), layout, 60.0).within_reach(line, np.ones(1, bool)) is not None
