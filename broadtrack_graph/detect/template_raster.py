"""The pitch template as seen by a camera: dense image samples per class, and a drawn mask.

Shared by the weight-free detector (naming ridge points by their nearest projected
marking), the confidence measure and the pictures. The 3D samples of
:class:`~broadtrack_graph.reinit.linefit.TemplateCurves` (metres apart) are projected
and the pieces of polyline in front of the camera are densified in the image, so that
nearest-sample distances are point-to-curve distances to within a fraction of a pixel.
No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.linefit import TemplateCurves
from broadtrack_graph.geometry.pitch import LINE_CLASSES


@dataclass
class ImageTemplate:
    """Dense projected template samples of one camera.

    uv_px: (N, 2) pixels at the requested size; class_index: (N,) index into LINE_CLASSES;
    width_m_px: (N,) image width (pixels) of a 12 cm wide marking at each sample (how visible it is).
    """

    uv_px: np.ndarray
    class_index: np.ndarray
    width_m_px: np.ndarray


MARKING_WIDTH_M = 0.12
"""Painted line width (metres) used to judge whether a marking is wide enough to be detected."""


def finite_runs(ok: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) index pairs of the runs of True in a (L,) bool array that hold at least 2 samples."""
    flags = np.concatenate([[False], np.asarray(ok, bool), [False]]).astype(np.int8)
    edges = np.flatnonzero(np.diff(flags))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2]) if b - a >= 2]


def _usable(uv: np.ndarray, front: np.ndarray, width_px: int, height_px: int, margin: float = 2.0) -> np.ndarray:
    """In front of the camera, finite, and not absurdly far off the image (distortion folds far points back)."""
    limit = margin * max(width_px, height_px)
    ok = front & np.all(np.isfinite(uv), axis=1)
    with np.errstate(invalid="ignore"):
        ok &= (uv[:, 0] > -limit) & (uv[:, 0] < width_px + limit) & (uv[:, 1] > -limit) & (uv[:, 1] < height_px + limit)
    return ok


def project_template(camera: Camera, curves: TemplateCurves, width_px: int, height_px: int, spacing_px: float = 1.0,
                     classes=None, inside_only: bool = True) -> ImageTemplate:
    """Project every class and densify each visible polyline piece to about ``spacing_px``.

    Args:
        camera: any resolution (rescaled to width_px x height_px).
        classes: class names (default: the ground classes, the ones painted on the grass).
        inside_only: keep only samples inside the image.
    """
    cam = camera if (camera.width_px, camera.height_px) == (width_px, height_px) else camera.rescaled(width_px, height_px)
    names = classes if classes is not None else [n for n in LINE_CLASSES if curves.pitch.is_on_ground(n)]
    index = {n: j for j, n in enumerate(LINE_CLASSES)}
    uv_all, cls_all, wid_all = [], [], []
    r3 = cam.R_cw[2]
    for name in names:
        samples = curves.samples_w[name]
        uv, front = cam.project(samples)
        depth = (samples - cam.position_m) @ r3
        ok = _usable(uv, front, width_px, height_px)
        for a, b in finite_runs(ok):
            run, run_depth = uv[a:b], depth[a:b]
            lo, hi = np.minimum(run[:-1], run[1:]), np.maximum(run[:-1], run[1:])
            # Only segments whose bounding box meets the image (grown by 2 px) are densified.
            near = (hi[:, 0] >= -2) & (lo[:, 0] <= width_px + 1) & (hi[:, 1] >= -2) & (lo[:, 1] <= height_px + 1)
            if not near.any():
                continue
            first = np.flatnonzero(near)
            step = np.linalg.norm(run[first + 1] - run[first], axis=1)
            count = np.maximum(np.ceil(step / spacing_px).astype(int), 1)
            # Piecewise-linear densification of each kept segment, both ends included.
            seg = np.repeat(first, count + 1)
            t = (np.arange(int(count.sum() + len(count))) - np.repeat(np.cumsum(count + 1) - (count + 1), count + 1)
                 ) / np.repeat(count, count + 1)
            pts = run[seg] + t[:, None] * (run[seg + 1] - run[seg])
            dep = run_depth[seg] + t * (run_depth[seg + 1] - run_depth[seg])
            uv_all.append(pts)
            wid_all.append(MARKING_WIDTH_M * cam.focal_px / np.maximum(dep, 1e-3))
            cls_all.append(np.full(len(pts), index[name], np.int16))
    if not uv_all:
        return ImageTemplate(np.zeros((0, 2)), np.zeros(0, np.int16), np.zeros(0))
    uv, cls, wid = np.vstack(uv_all), np.concatenate(cls_all), np.concatenate(wid_all)
    if inside_only:
        keep = (uv[:, 0] >= 0) & (uv[:, 0] <= width_px - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= height_px - 1)
        uv, cls, wid = uv[keep], cls[keep], wid[keep]
    return ImageTemplate(uv, cls, wid)


def template_mask(camera: Camera, curves: TemplateCurves, width_px: int, height_px: int, thickness_px: int = 1,
                  classes=LINE_CLASSES) -> np.ndarray:
    """(H, W) bool: the projected template drawn as lines of the given thickness."""
    canvas = np.zeros((height_px, width_px), dtype=np.uint8)
    cam = camera if (camera.width_px, camera.height_px) == (width_px, height_px) else camera.rescaled(width_px, height_px)
    for name in classes:
        uv, front = cam.project(curves.samples_w[name])
        for a, b in finite_runs(_usable(uv, front, width_px, height_px)):
            cv2.polylines(canvas, [np.round(uv[a:b]).astype(np.int32)], False, 255, max(1, int(thickness_px)))
    return canvas > 0
