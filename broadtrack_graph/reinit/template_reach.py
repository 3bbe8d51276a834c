"""How much of a true camera's template the detector finds, by a property of each marking: the tallies ``bench
placements --random`` reports (:mod:`broadtrack_graph.benchmarks.placement_found`), what the confidence's rules of
what is expected were read from. The samples and the finding are the confidence's own
(:mod:`~broadtrack_graph.reinit.confidence`). No I/O.
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from broadtrack_graph.detect.motion_blur import MotionBlur
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pixel_neighbours import pixels_within
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.confidence import (
    ComparedSets,
    ConfidenceConfig,
    compared_sets,
    found_near,
    smeared_contrast,
)


def found_by_paint_width(camera: Camera, marking_mask: np.ndarray, edges_px: np.ndarray, curves: TemplateCurves,
                         config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None,
                         player_mask: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(B,) template samples of ``camera`` wide enough by their scale (``min_line_width_px``) whose painted width
    (working pixels) falls in each bin ``[edges_px[b], edges_px[b + 1])``, and (B,) of them within the tolerance of a
    marking of the map: how often the detector finds paint of each width, what ``min_paint_width_px`` is read from
    (on true cameras)."""
    compared = compared_sets(camera, marking_mask, curves, replace(config, min_paint_width_px=0.0), field_mask,
                         player_mask)
    return _found_by_bins(compared, compared.paint_px, edges_px, config)


def found_by_smeared_contrast(camera: Camera, marking_mask: np.ndarray, motion_blur: MotionBlur, edges: np.ndarray,
                              curves: TemplateCurves, config: ConfidenceConfig = ConfidenceConfig(),
                              field_mask: np.ndarray | None = None, player_mask: np.ndarray | None = None
                              ) -> tuple[np.ndarray, np.ndarray]:
    """(B,) detectable template samples of ``camera`` (as on a sharp frame) whose share of contrast left by the
    frame's motion blur (:func:`smeared_contrast`) falls in each bin ``[edges[b], edges[b + 1])``, and (B,) of them
    within the tolerance of a marking of the map: what ``min_smeared_contrast`` is read from (on true cameras)."""
    compared = compared_sets(camera, marking_mask, curves, config, field_mask, player_mask)
    smear = replace(motion_blur, length_px=motion_blur.length_px * compared.size[0] / camera.width_px)
    share = smeared_contrast(compared.uv, compared.class_index, compared.paint_px, smear)
    return _found_by_bins(compared, share, edges, config)


def found_by_map_value(camera: Camera, marking_mask: np.ndarray, value_map: np.ndarray, edges: np.ndarray,
                       curves: TemplateCurves, config: ConfidenceConfig = ConfidenceConfig(),
                       field_mask: np.ndarray | None = None, player_mask: np.ndarray | None = None
                       ) -> tuple[np.ndarray, np.ndarray]:
    """(B,) detectable template samples of ``camera`` whose value on ``value_map`` (its largest within a pixel of the
    sample: a sample lies on its marking within about a pixel) falls in each bin ``[edges[b], edges[b + 1])``, and (B,)
    of them within the tolerance of a marking of the map: how often the detector finds a marking by a property of the
    image along it (the top-hat contrast of its paint, on true cameras).

    Args:
        value_map: (h, w) float or integer map, any size of the frame's aspect ratio (read at the working size).
    """
    compared = compared_sets(camera, marking_mask, curves, config, field_mask, player_mask)
    w, h = compared.size
    values = cv2.resize(np.asarray(value_map, np.float32), (w, h), interpolation=cv2.INTER_NEAREST) \
        if value_map.shape[:2] != (h, w) else np.asarray(value_map, np.float32)
    values = cv2.dilate(values, np.ones((3, 3), np.uint8))
    col = np.clip(np.round(compared.uv[:, 0]).astype(int), 0, w - 1)
    row = np.clip(np.round(compared.uv[:, 1]).astype(int), 0, h - 1)
    return _found_by_bins(compared, values[row, col], edges, config)


def _found_by_bins(compared: ComparedSets, values: np.ndarray, edges: np.ndarray, config: ConfidenceConfig
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(B,) the detectable samples of ``compared`` whose value (N,) falls in each bin of ``edges`` (B + 1,), and (B,)
    of them found on its map."""
    bins = np.digitize(values[compared.detectable], edges) - 1
    inside = (bins >= 0) & (bins < len(edges) - 1)
    found = np.zeros(len(compared.uv), bool)
    if len(compared.uv):
        near, pixel = pixels_within(compared.uv, compared.size, config.tolerance_px)
        found = found_near(compared.marks, near, pixel)
    samples = np.bincount(bins[inside], minlength=len(edges) - 1)
    hits = np.bincount(bins[inside], weights=found[compared.detectable][inside], minlength=len(edges) - 1)
    return samples, hits.astype(int)
