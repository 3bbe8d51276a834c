"""How wide a painted line is in the image: its 12 cm strip on the grass projected, across the line's image. No I/O.

A marking's scale ``f / depth`` says how many pixels 12 cm span at its depth in any direction; the paint itself is
a strip on the grass, and seen at a grazing angle across the line of sight it is foreshortened to a fraction of that
(the far lines across a low camera's view, ten to twenty times thinner), while a line along the line of sight is
not. :func:`painted_widths_px` measures it from the strip's two edges.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera

MARKING_WIDTH_M = 0.12
"""Painted line width (metres) used to judge whether a marking is wide enough to be detected."""


def painted_widths_px(camera: Camera, points_w: np.ndarray, uv_px: np.ndarray, joins_next: np.ndarray) -> np.ndarray:
    """(S,) image width (pixels) of a :data:`MARKING_WIDTH_M` painted line at each of the stacked template samples
    ``points_w`` (S, 3) metres (``uv_px`` (S, 2): their projections by ``camera``; ``joins_next`` (S - 1,): sample i
    and i + 1 on one polyline): the strip's two edges, half the width either side of the line on the grass,
    projected, their offset taken across the line's image. NaN where the line's direction or an edge's image is
    unknown (a lone sample, an edge behind the camera)."""
    after = np.append(joins_next, False)
    before = np.insert(joins_next, 0, False)

    def along(values):
        return np.where(after[:, None], np.roll(values, -1, axis=0) - values,
                        np.where(before[:, None], values - np.roll(values, 1, axis=0), np.nan))

    tangent_w = along(points_w)
    across_w = np.column_stack([-tangent_w[:, 1], tangent_w[:, 0], np.zeros(len(tangent_w))])
    with np.errstate(invalid="ignore", divide="ignore"):
        across_w *= 0.5 * MARKING_WIDTH_M / np.linalg.norm(across_w, axis=1, keepdims=True)
        edge_a, _ = camera.project(points_w + across_w)
        edge_b, _ = camera.project(points_w - across_w)
        tangent_px = along(uv_px)
        offset = edge_a - edge_b
        return np.abs(offset[:, 0] * tangent_px[:, 1] - offset[:, 1] * tangent_px[:, 0]) / np.linalg.norm(tangent_px,
                                                                                                           axis=1)
