"""Pictures of single-frame calibrations (no image needed): one frame, and a mosaic of several."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves


def draw_calibration(lines_norm: dict[str, np.ndarray], camera: Camera | None, width_px: int, height_px: int,
                     tau_px: float = 5.0, title: str = "") -> np.ndarray:
    """A picture of one calibrated frame (no image needed): (H, W, 3) uint8 BGR.

    Dark canvas, the camera's projected template in magenta, annotated points in green
    when within tau_px of their class (mirrored labelling allowed, as the metric does),
    red otherwise; the frame's JaC@tau in the corner.
    """
    import cv2

    from broadtrack_graph.detect.template_raster import template_mask
    from broadtrack_graph.metrics.soccernet import evaluate_frame

    canvas = np.full((height_px, width_px, 3), 35, np.uint8)
    text = title
    outcome = {}
    if camera is not None:
        canvas[template_mask(camera, TemplateCurves(), width_px, height_px, 1)] = (200, 0, 200)
        score = evaluate_frame(lines_norm, camera, width_px, height_px, (tau_px,))
        outcome = score.distances[tau_px]
        text += f"  JaC@{tau_px:g} {score.jac[tau_px]:.2f}" + (" (mirrored)" if score.mirrored[tau_px] else "")
    else:
        text += "  no camera"
    scale = np.array([width_px - 1, height_px - 1], dtype=float)
    from broadtrack_graph.geometry.pitch import MIRRORED_CLASS

    for name, points in lines_norm.items():
        distances = outcome.get(name, outcome.get(MIRRORED_CLASS.get(name, name)))
        for k, (u, v) in enumerate(np.asarray(points) * scale):
            good = distances is not None and k < len(distances) and distances[k] < tau_px
            cv2.circle(canvas, (int(round(u)), int(round(v))), 3, (0, 220, 0) if good else (0, 0, 255), -1)
    cv2.putText(canvas, text, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 1, cv2.LINE_AA)
    return canvas


def write_mosaic(pictures: list[np.ndarray], path: str | Path) -> None:
    """Write pictures (each (H, W, 3) uint8 BGR, same size) as a PNG mosaic, 3 per row, at half size.

    A last row that is not full is padded with black pictures.
    """
    import cv2

    pictures = list(pictures) + [np.zeros_like(pictures[0])] * (-len(pictures) % 3)
    rows = [np.hstack(pictures[i:i + 3]) for i in range(0, len(pictures), 3)]
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mosaic = np.vstack(rows)
    cv2.imwrite(str(path), cv2.resize(mosaic, (mosaic.shape[1] // 2, mosaic.shape[0] // 2), interpolation=cv2.INTER_AREA))
