"""Cameras along a camera's line of sight, for the ill-determined depth of an exact fit or a narrow view. No I/O.

A circle and one line fix a camera exactly: seven constraints for its seven unknowns. Read from an ellipse fitted
to a few hundred marking pixels, the conic's error moves the fitted camera mostly along one direction: towards or
away from the ground point it looks at, the focal length changing with the distance so that the markings in view
keep their size in the image (a narrow view is nearly affine, and the two trade off). The markings in view are
drawn about as well all along that valley, the rest of the template is not: a fit that stopped metres off along it
draws the markings out of view where the frame shows none. :func:`along_line_of_sight` gives the starts of fits
spread along it; the confidence, which reads the whole template in view, chooses among them
(:func:`most_confident_along_line_of_sight`). Any fit of a narrow view lies in the same valley: with many markings in
view, a fit started metres off along it can stop there, each marking a few pixels off.

Conventions: pitch frame in metres, origin at the centre spot, z down (the ground is z = 0).
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.mask import refine_on_map
from broadtrack_graph.reinit.mask_config import MaskSearchConfig


def along_line_of_sight(camera: Camera, factors) -> list[Camera]:
    """``camera`` moved along its optical axis, one camera per factor: its focal point at ``factor`` times its
    distance from the ground point it looks at (the image centre's), its focal length times ``factor`` (that point's
    surroundings drawn about the same size), its angles and k1 kept. Empty when the optical axis does not meet the
    ground ahead of the camera (a view above the horizon).

    Args:
        camera: the camera to move.
        factors: (F,) positive distance factors (1 gives the camera itself).
    """
    axis = camera.optical_axis_w
    position = np.asarray(camera.position_m, float)
    if axis[2] <= 1e-6 or position[2] >= 0:  # z down: the axis must descend from above the grass
        return []
    look_at = position + (-position[2] / axis[2]) * axis
    return [camera.replace(focal_px=camera.focal_px * float(k), position_m=look_at + (position - look_at) * float(k))
            for k in factors]


def most_confident_along_line_of_sight(camera: Camera, points_px: np.ndarray, curves: TemplateCurves,
                                       search: MaskSearchConfig, factors, confidence_of) -> Camera | None:
    """The most confident of the cameras fitted to the marking points from starts along ``camera``'s line of sight
    (:func:`along_line_of_sight` at ``factors``; the label-and-fit rounds of
    :func:`~broadtrack_graph.reinit.mask.refine_on_map`), when more confident than ``camera`` itself; else None.

    Args:
        points_px: (M, 2) marking points the fits use, frame pixels.
        confidence_of: camera -> its confidence on the frame's markings.
    """
    best, best_confidence = None, confidence_of(camera)
    for start in along_line_of_sight(camera, factors):
        fitted = refine_on_map(start, points_px, start.position_m, curves, search, search.schedule)
        confidence = confidence_of(fitted)
        if confidence > best_confidence:
            best, best_confidence = fitted, confidence
    return best
