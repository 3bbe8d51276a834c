"""The weight-free detector's naming rule: the markings points are named after, which points named after a class stay,
and their cell means. No I/O.

A predicted camera's error shifts a whole marking about equally, so the points named after one class lie at about
the same distance from its predicted marking; points much nearer or farther are other markings or clutter.
Vectorised over every class at once (one sort, one key), the same numbers as the rule applied class by class.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.detect.point_cells import capped_cell_means
from broadtrack_graph.geometry.pitch import LINE_CLASSES


def seen_markings(width_at_scale_px: np.ndarray, paint_width_px: np.ndarray | None, min_width_px: float,
                  min_paint_px: float) -> np.ndarray:
    """(K,) bool: the projected template samples points may be named after: a marking at least ``min_width_px`` wide
    at its scale (its width seen face on), or whose paint is at least ``min_paint_px`` across its image (None: not
    asked). A wide view's far lines, thin by their distance, are seen face on; a low camera's far touchline, its paint
    foreshortened to a tenth of a pixel beside the boards' base, is neither (the boards' base would be named).

    Args:
        width_at_scale_px: (K,) a marking's width at each sample's scale; paint_width_px: (K,) its paint across the
            image (``geometry.template.ImageTemplate``, both in the same pixels as the thresholds).
    """
    seen = np.asarray(width_at_scale_px) >= min_width_px
    return seen if paint_width_px is None else seen | (np.asarray(paint_width_px) >= min_paint_px)


def _group_medians(values: np.ndarray, starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """np.median of each group of ``values`` (sorted within each group; group g is values[starts[g]:][:counts[g]])."""
    return 0.5 * (values[starts + (counts - 1) // 2] + values[starts + counts // 2])


def consistent_classes(points_px: np.ndarray, classes: np.ndarray, distance_px: np.ndarray, consistency_px: float,
                       min_points: int, spacing_px: float, max_points: int) -> dict[str, np.ndarray]:
    """The named points of each class: those whose distance to their predicted marking is near the class's median
    distance (within 2.5 robust sigmas, at least ``consistency_px``: the prediction error shifts a whole
    marking about equally, other markings and clutter are off), averaged per cell of ``spacing_px`` (at most ``max_points`` cells,
    :func:`~broadtrack_graph.detect.point_cells.capped_cell_means`); classes with fewer than
    ``min_points`` left are dropped. All classes at once (sorted by class, then distance).

    Args:
        points_px: (N, 2) working pixels; classes: (N,) their class indices; distance_px: (N,) to the prediction.
    """
    if not len(points_px):
        return {}
    order = np.lexsort((distance_px, classes))
    names, starts, counts = np.unique(classes[order], return_index=True, return_counts=True)
    median = _group_medians(distance_px[order], starts, counts)
    group = np.repeat(np.arange(len(names)), counts)  # each sorted point's group
    deviation = np.abs(distance_px[order] - median[group])
    by_deviation = np.lexsort((deviation, group))
    spread = np.maximum(consistency_px, 2.5 * 1.4826 * _group_medians(deviation[by_deviation], starts, counts))
    index_group = np.searchsorted(names, classes)
    keep = np.abs(distance_px - median[index_group]) <= spread[index_group]
    enough = np.bincount(index_group[keep], minlength=len(names)) >= min_points
    keep &= enough[index_group]
    if not keep.any():
        return {}
    # Each class's cell means (point_cells.cell_means) at once: the class is the key's leading part.
    kept, kept_group = points_px[keep], index_group[keep]
    cells = np.floor(kept / spacing_px).astype(np.int64)
    cells -= cells.min(axis=0)  # non-negative: the class stays the key's leading part (the cells' order is kept)
    keys = kept_group * (1 << 40) + cells[:, 0] * 1_000_003 + cells[:, 1]
    unique_keys, inverse, cell_counts = np.unique(keys, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    means = np.column_stack([np.bincount(inverse, kept[:, 0]), np.bincount(inverse, kept[:, 1])]) / cell_counts[:, None]
    cell_group = unique_keys >> 40
    out = {}
    for g in np.flatnonzero(enough):
        class_means = means[cell_group == g]
        if max_points > 0 and len(class_means) > max_points:
            class_means = capped_cell_means(kept[kept_group == g], spacing_px, max_points)
        out[LINE_CLASSES[names[g]]] = class_means
    return out
