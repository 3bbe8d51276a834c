"""Does the confidence mean what it says? Cameras judged right or wrong, and the reliability table.

A written camera comes with a confidence in [0, 1]. The reliability table groups the written cameras
by confidence and shows, per group, the share that is right: a confidence that means what it says has
every group's share right near its confidence, and the groups above the tracker's threshold near 1.

What "right" means here, without the tracker's own detector:

* against a true camera (synthetic frames): every pitch marking the true camera shows is laid
  by the camera within a few pixels of where the true camera lays it, at the SoccerNet metric's
  resolution (960 x 540): :func:`line_disagreement_px`;
* on real frames: the independent line-alignment check
  (:mod:`broadtrack_graph.metrics.line_alignment`), computed by the caller.

No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateSampling, distances_to_polyline, project_template_polylines

DEFAULT_EDGES = (0.0, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
"""Confidence bins of the table: [0, 0.3), [0.3, 0.4), ..., [0.9, 1.0] (the last one closed)."""

MIN_VISIBLE_SAMPLES = 10
"""A true camera showing fewer template samples than this judges nothing (the frame is left out)."""


def line_disagreement_px(camera: Camera, truth: Camera, sampling: TemplateSampling, width_px: int = 960,
                         height_px: int = 540) -> float | None:
    """How far ``camera`` lays the pitch markings that ``truth`` shows from where ``truth`` lays them: the largest
    distance (pixels at ``width_px`` x ``height_px``) of a marking's samples projected by ``truth`` (inside the
    image) to the same marking's polyline projected by ``camera``, over every marking ``truth`` shows.

    As the SoccerNet metric measures an annotated marking against a projected one (a point's distance to the
    polyline, so that a grazing line may slide along itself), but against the true camera's projection instead of
    an annotation, and with the class names as they are (a camera turned half a turn about the pitch's centre is
    wrong here).

    Args:
        camera, truth: the camera judged and the true camera of the same frame (any resolution, same aspect).
        sampling: the template's samples (:class:`~broadtrack_graph.geometry.template.TemplateSampling`).
        width_px, height_px: the resolution the distance is measured at.

    Returns:
        The distance in pixels, or None when ``truth`` shows fewer than :data:`MIN_VISIBLE_SAMPLES` samples in all.
        A marking ``camera`` lays outside the image (or behind itself) counts as far off as its shown part reaches
        into the image: a sliver at the border is a small error, a marking across the image a large one.
    """
    shown = project_template_polylines(truth, width_px, height_px, sampling)
    if sum(len(points) for points in shown.values()) < MIN_VISIBLE_SAMPLES:
        return None
    laid = project_template_polylines(camera, width_px, height_px, sampling)
    worst = 0.0
    for name, points in shown.items():
        if name in laid:
            worst = max(worst, float(distances_to_polyline(points, laid[name]).max()))
        else:  # laid outside the image: at least as far as the shown part is from the image's border
            border = np.minimum.reduce([points[:, 0], width_px - 1 - points[:, 0], points[:, 1],
                                        height_px - 1 - points[:, 1]])
            worst = max(worst, float(np.max(border)))
    return worst


@dataclass(frozen=True)
class ReliabilityRow:
    """One confidence bin: [low, high), the cameras in it and the share of them that is right."""

    low: float
    high: float
    cameras: int
    right: int

    @property
    def right_share(self) -> float | None:
        return self.right / self.cameras if self.cameras else None

    def as_dict(self) -> dict:
        share = self.right_share
        return {"confidence": f"{self.low:.1f}-{self.high:.1f}", "cameras": self.cameras, "right": self.right,
                "right_share": None if share is None else round(share, 4)}


def reliability_table(confidence, right, edges=DEFAULT_EDGES) -> list[ReliabilityRow]:
    """Written cameras grouped by confidence.

    Args:
        confidence: (N,) the confidence of each written camera (NaN: left out).
        right: (N,) bool, the camera is right.
        edges: (B + 1,) increasing bin edges; the last bin includes its upper edge.

    Returns:
        B rows, lowest confidence first.
    """
    confidence = np.asarray(confidence, float).reshape(-1)
    right = np.asarray(right, bool).reshape(-1)
    if confidence.shape != right.shape:
        raise ValueError(f"{confidence.shape[0]} confidences for {right.shape[0]} verdicts")
    keep = np.isfinite(confidence)
    confidence, right = confidence[keep], right[keep]
    edges = np.asarray(edges, float)
    index = np.clip(np.searchsorted(edges, confidence, side="right") - 1, 0, len(edges) - 2)
    return [ReliabilityRow(float(edges[b]), float(edges[b + 1]), int(np.count_nonzero(index == b)),
                           int(np.count_nonzero(right[index == b]))) for b in range(len(edges) - 1)]


def reliability_summary(confidence, right, edges=DEFAULT_EDGES) -> dict:
    """The table as JSON-ready rows, with the share right among all the cameras (``written_right_share``)."""
    rows = reliability_table(confidence, right, edges)
    cameras, good = sum(r.cameras for r in rows), sum(r.right for r in rows)
    return {"rows": [r.as_dict() for r in rows], "cameras": cameras,
            "written_right_share": round(good / cameras, 4) if cameras else None}


def merged_summaries(summaries: list[dict]) -> dict | None:
    """Several :func:`reliability_summary` results (same bins) added up."""
    summaries = [s for s in summaries if s and s.get("rows")]
    if not summaries:
        return None
    rows = []
    for parts in zip(*(s["rows"] for s in summaries)):
        cameras, good = sum(p["cameras"] for p in parts), sum(p["right"] for p in parts)
        rows.append({"confidence": parts[0]["confidence"], "cameras": cameras, "right": good,
                     "right_share": round(good / cameras, 4) if cameras else None})
    cameras, good = sum(r["cameras"] for r in rows), sum(r["right"] for r in rows)
    return {"rows": rows, "cameras": cameras, "written_right_share": round(good / cameras, 4) if cameras else None}
