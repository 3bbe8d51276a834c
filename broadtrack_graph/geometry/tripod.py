"""The tripod model of BroadTrack (WACV 2025; see docs/METHOD.md): the camera turns on a fixed pan/tilt head.

The pan and tilt axes of the head meet at a fixed point T_w. A point O on the
optical axis stays at distance delta from T (O = T - delta * r2, with -r2 the
camera's up vector), and the focal point slides along the optical axis with zoom:

    C = T - delta * r2 + lambda * r3

where r_i are the columns of R_cw^T (r3 the optical axis). The cost used by the
tracker is ``L_T = delta - |O* - T|`` with O* the point of the optical axis closest
to T. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Tripod:
    """T_w: (3,) pan/tilt axes meeting point, metres, pitch frame (z down); delta_m: offset of the optical axis;
    sigma_m: how uncertain T_w is (metres; 0 for a fitted or given tripod, a provisional tripod's from the scatter of
    the cameras it was made from): a tripod held fixed holds the camera no tighter than that."""

    T_w: tuple[float, float, float]
    delta_m: float
    sigma_m: float = 0.0

    def as_vector(self) -> np.ndarray:
        """[Tx, Ty, Tz, delta] (metres)."""
        return np.array([*self.T_w, self.delta_m], dtype=float)

    @classmethod
    def from_vector(cls, vector) -> "Tripod":
        v = np.asarray(vector, dtype=float).reshape(4)
        return cls((float(v[0]), float(v[1]), float(v[2])), float(v[3]))


def focal_point(R_cw: np.ndarray, tripod: Tripod, lambda_m: float) -> np.ndarray:
    """C_w = T - delta * r2 + lambda * r3 for a world-to-camera rotation R_cw (3, 3)."""
    r2 = R_cw[1]  # second column of R^T
    r3 = R_cw[2]  # third column of R^T: the optical axis
    return np.asarray(tripod.T_w, dtype=float) - tripod.delta_m * r2 + lambda_m * r3


def closest_axis_point(C_w: np.ndarray, R_cw: np.ndarray, T_w: np.ndarray) -> np.ndarray:
    """O*: the point of the optical axis (through C_w along r3) closest to T_w."""
    axis = R_cw[2]
    return C_w + np.dot(np.asarray(T_w) - C_w, axis) * axis


def tripod_residual(C_w: np.ndarray, R_cw: np.ndarray, tripod: Tripod) -> float:
    """L_T = delta - |O* - T| (metres); zero for a camera on the tripod."""
    T = np.asarray(tripod.T_w, dtype=float)
    return float(tripod.delta_m - np.linalg.norm(closest_axis_point(np.asarray(C_w, float), R_cw, T) - T))


def zoom_lambda(C_w: np.ndarray, R_cw: np.ndarray, tripod: Tripod) -> float:
    """lambda: position of C along the optical axis relative to O (metres)."""
    O = np.asarray(tripod.T_w, dtype=float) - tripod.delta_m * R_cw[1]
    return float(np.dot(np.asarray(C_w, float) - O, R_cw[2]))


def image_motion_vector(previous, camera) -> np.ndarray:
    """(2,) how the image moves at its centre from one camera of a tripod to the next (pixels at the camera's size):
    where the direction seen at the previous image's centre lands, less the centre (a turn of the camera; the
    focal point's move of centimetres is left out, as by :func:`image_motion_px`).

    Args:
        previous, camera: :class:`~broadtrack_graph.geometry.camera.Camera` of consecutive frames (the same size).
    """
    centre = np.array([[0.5 * (camera.width_px - 1), 0.5 * (camera.height_px - 1)]])
    far = camera.position_m + 1e4 * previous.backproject(centre)[0]  # the direction, from the new focal point
    uv, front = camera.project(far[None])
    if not front[0] or not np.all(np.isfinite(uv)):
        return np.zeros(2)
    return uv[0] - centre[0]


def image_motion_px(previous, camera, reference_width_px: float = 960.0) -> float:
    """How far the image moves from one camera of a tripod to the next (pixels at ``reference_width_px`` wide): the
    turn of the optical axis (radians) times the focal length, plus the zoom's move at the image's side edges
    (``|log(f1 / f0)|`` times half the width). A translation of the focal point is left out (centimetres a frame).

    Args:
        previous, camera: :class:`~broadtrack_graph.geometry.camera.Camera` of consecutive frames (the same size).
    """
    turn = math.acos(float(np.clip(previous.R_cw[2] @ camera.R_cw[2], -1.0, 1.0)))
    zoom = abs(math.log(camera.focal_px / previous.focal_px)) * camera.width_px / 2.0
    return (turn * camera.focal_px + zoom) * reference_width_px / camera.width_px
