"""The SoccerNet broadcast camera: rotation conventions, projection, back-projection.

Conventions (SoccerNet's, kept exactly):

* World frame: origin at the centre spot, x towards the right goal, +y towards the
  near touchline, z DOWN (a camera above the pitch has negative z).
* Rotation world -> camera: ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T`` with
  ``Rz(a) = [[c,-s,0],[s,c,0],[0,0,1]]`` and ``Rx(t) = [[1,0,0],[0,c,-s],[0,s,c]]``
  (the builders of :mod:`broadtrack_graph.geometry.state`, shared with the tracker state).
  tilt 0 looks straight down, tilt 90 deg looks horizontally, pan 0 looks
  towards -y, positive pan turns towards +x.
* Projection: ``Xc = R_cw (X_w - C_w)``; a point with ``Xc_z <= 1e-3`` is behind
  the camera; ``x_n = Xc_xy / Xc_z``; ``uv = f * distort(x_n) + principal point``.
* Distortion: SoccerNet's rational radial model (k1..k3 over k4..k6), tangential
  (p1, p2) and thin prism (s1..s4), all in normalised coordinates
  (:mod:`broadtrack_graph.geometry.distortion`). The tracker
  estimates k1 only; the other terms are carried so that files from other tools
  are projected with their full model.
* The principal point is the image centre ``(W / 2, H / 2)`` unless a file says
  otherwise.
* The tracker's 8-vector (:meth:`Camera.to_vector`) is the state of
  :mod:`broadtrack_graph.geometry.state` (order :data:`~broadtrack_graph.geometry.state.STATE_NAMES`).

This module does no I/O: :mod:`broadtrack_graph.io.cameras` reads and writes files.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from broadtrack_graph.geometry.distortion import (
    NO_EXTRA_DISTORTION,
    ExtraDistortion,
    distort_normalized,
    undistort_normalized,
    unfolded_radius2,
)
from broadtrack_graph.geometry.shapes import check_points
from broadtrack_graph.geometry.state import (
    BEHIND_CAMERA_Z,
    FOCAL,
    K1,
    PAN,
    POSITION,
    ROLL,
    STATE_SIZE,
    TILT,
    rotation_from_angles,
)

# --------------------------------------------------------------------------- rotations


def angles_from_rotation(R_cw: np.ndarray) -> tuple[float, float, float]:
    """Pan, tilt and roll (radians) of a world-to-camera rotation.

    Two (pan, tilt, roll) triples give the same matrix (tilt and -tilt); the one
    whose roll is nearest 0 is returned, as camera operators keep roll small.
    At tilt 0 or 180 deg only pan + roll is defined; roll is then set to 0.

    Args:
        R_cw: (3, 3) rotation matrix, world to camera.

    Returns:
        (pan_rad, tilt_rad, roll_rad).
    """
    orientation = np.asarray(R_cw, dtype=float).T  # Rz(pan) Rx(tilt) Rz(roll)
    cos_tilt = float(np.clip(orientation[2, 2], -1.0, 1.0))
    sin_tilt_abs = math.hypot(orientation[2, 0], orientation[2, 1])
    if sin_tilt_abs < 1e-12:
        # Gimbal lock: orientation = Rz(pan +- roll); choose roll = 0.
        tilt = 0.0 if cos_tilt > 0 else math.pi
        pan = math.atan2(orientation[1, 0], orientation[0, 0])
        return pan, tilt, 0.0
    best = None
    for sign in (1.0, -1.0):
        tilt = math.atan2(sign * sin_tilt_abs, cos_tilt)
        pan = math.atan2(sign * orientation[0, 2], -sign * orientation[1, 2])
        roll = math.atan2(sign * orientation[2, 0], sign * orientation[2, 1])
        if best is None or abs(roll) < abs(best[2]):
            best = (pan, tilt, roll)
    return best


# --------------------------------------------------------------------------- camera


@dataclass(frozen=True, eq=False)
class Camera:
    """An immutable broadcast camera in the SoccerNet convention.

    Attributes:
        focal_px: focal length in pixels at (width_px, height_px); square pixels.
        k1: first radial distortion coefficient, normalised coordinates.
        pan_rad, tilt_rad, roll_rad: orientation (see module docstring).
        position_m: (3,) focal point C_w in metres, pitch frame (z down).
        width_px, height_px: the image size the intrinsics refer to.
        extra_distortion: k2..k6, tangential and thin-prism terms (zero for our own tracks).
        principal_point_px: (cx, cy); None means the image centre (W / 2, H / 2).
    """

    focal_px: float
    k1: float
    pan_rad: float
    tilt_rad: float
    roll_rad: float
    position_m: np.ndarray
    width_px: int
    height_px: int
    extra_distortion: ExtraDistortion = NO_EXTRA_DISTORTION
    principal_point_px: tuple[float, float] | None = None
    _R_cw: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        position = np.asarray(self.position_m, dtype=float).reshape(3).copy()
        position.setflags(write=False)
        object.__setattr__(self, "position_m", position)
        values = (self.focal_px, self.k1, self.pan_rad, self.tilt_rad, self.roll_rad, *position)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"camera has a non-finite parameter: {values}")
        if self.focal_px <= 0:
            raise ValueError(f"focal_px must be positive, got {self.focal_px}")
        if self.width_px <= 0 or self.height_px <= 0:
            raise ValueError(f"image size must be positive, got {self.width_px}x{self.height_px}")
        R = rotation_from_angles(self.pan_rad, self.tilt_rad, self.roll_rad)
        R.setflags(write=False)
        object.__setattr__(self, "_R_cw", R)

    # ----------------------------------------------------------------- construction

    @classmethod
    def from_degrees(
        cls,
        focal_px: float,
        k1: float,
        pan_deg: float,
        tilt_deg: float,
        roll_deg: float,
        position_m,
        width_px: int,
        height_px: int,
        **kwargs,
    ) -> "Camera":
        """Build a camera with angles given in degrees."""
        return cls(
            focal_px, k1, math.radians(pan_deg), math.radians(tilt_deg), math.radians(roll_deg),
            np.asarray(position_m, dtype=float), width_px, height_px, **kwargs,
        )

    @classmethod
    def from_vector(cls, state: np.ndarray, width_px: int, height_px: int) -> "Camera":
        """Camera from the tracker's 8-vector ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]`` (px, -, radians, metres).

        Args:
            state: (8,) in the order of :data:`broadtrack_graph.geometry.state.STATE_NAMES`.
            width_px, height_px: the image size f refers to.
        """
        s = np.asarray(state, dtype=float).reshape(STATE_SIZE)
        return cls(float(s[FOCAL]), float(s[K1]), float(s[PAN]), float(s[TILT]), float(s[ROLL]), s[POSITION],
                   width_px, height_px)

    def to_vector(self) -> np.ndarray:
        """(8,) the tracker's state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]`` (px, -, radians, metres)."""
        state = np.empty(STATE_SIZE)
        state[FOCAL], state[K1] = self.focal_px, self.k1
        state[PAN], state[TILT], state[ROLL] = self.pan_rad, self.tilt_rad, self.roll_rad
        state[POSITION] = self.position_m
        return state

    def replace(self, **changes) -> "Camera":
        """A copy with some fields changed (dataclasses.replace)."""
        return dataclasses.replace(self, **changes)

    # ----------------------------------------------------------------- derived

    @property
    def R_cw(self) -> np.ndarray:
        """(3, 3) world-to-camera rotation."""
        return self._R_cw

    @property
    def principal_point(self) -> np.ndarray:
        """(2,) principal point in pixels."""
        if self.principal_point_px is None:
            return np.array([self.width_px / 2.0, self.height_px / 2.0])
        return np.asarray(self.principal_point_px, dtype=float)

    @property
    def optical_axis_w(self) -> np.ndarray:
        """(3,) unit optical axis in the world frame (third column of R^T)."""
        return self._R_cw[2].copy()

    @property
    def pan_deg(self) -> float:
        return math.degrees(self.pan_rad)

    @property
    def tilt_deg(self) -> float:
        return math.degrees(self.tilt_rad)

    @property
    def roll_deg(self) -> float:
        return math.degrees(self.roll_rad)

    def rescaled(self, width_px: int, height_px: int) -> "Camera":
        """The same camera for another image resolution (f and principal point scale with width); this camera itself
        at its own resolution.

        k1 and the other distortion terms live in normalised coordinates and do not change.
        """
        if (int(width_px), int(height_px)) == (self.width_px, self.height_px):
            return self
        scale = width_px / self.width_px
        principal = None if self.principal_point_px is None else tuple(np.asarray(self.principal_point_px) * scale)
        return dataclasses.replace(
            self, focal_px=self.focal_px * scale, width_px=int(width_px), height_px=int(height_px),
            principal_point_px=principal,
        )

    # ----------------------------------------------------------------- projection

    def world_to_camera(self, points_w: np.ndarray) -> np.ndarray:
        """(N, 3) world points (metres) -> (N, 3) camera-frame points ``R_cw (X - C)``."""
        points_w = check_points(points_w, 3, "points_w")
        return (points_w - self.position_m) @ self._R_cw.T

    def project(self, points_w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Project world points to pixels with the full distortion model.

        Args:
            points_w: (N, 3) metres, pitch frame.

        Returns:
            uv_px: (N, 2) pixels at (width_px, height_px); NaN for points behind the camera or beyond the
                radius where the distortion folds back (:func:`unfolded_radius2`).
            in_front: (N,) bool, False where ``Xc_z <= 1e-3`` or the point lies beyond that radius (with
                k1 < 0 a point far outside the image would otherwise land inside it).
        """
        points_c = self.world_to_camera(points_w)
        depth = points_c[:, 2]
        in_front = depth > BEHIND_CAMERA_Z
        with np.errstate(invalid="ignore", divide="ignore"):
            xy_n = points_c[:, :2] / np.where(in_front, depth, np.nan)[:, None]
            in_front &= np.einsum("ij,ij->i", xy_n, xy_n) < unfolded_radius2(self.k1, self.extra_distortion)
        xy_n[~in_front] = np.nan
        xy_d = distort_normalized(xy_n, self.k1, self.extra_distortion)
        return self.focal_px * xy_d + self.principal_point, in_front

    def in_image(self, uv_px: np.ndarray) -> np.ndarray:
        """(N,) bool: pixel inside [0, W) x [0, H) (NaN counts as outside)."""
        uv_px = np.asarray(uv_px, dtype=float)
        with np.errstate(invalid="ignore"):
            return (
                (uv_px[:, 0] >= 0) & (uv_px[:, 0] < self.width_px) & (uv_px[:, 1] >= 0) & (uv_px[:, 1] < self.height_px)
            )

    def backproject(self, uv_px: np.ndarray) -> np.ndarray:
        """Pixels -> unit viewing rays in the world frame.

        Args:
            uv_px: (N, 2) pixels at (width_px, height_px).

        Returns:
            (N, 3) unit direction vectors in the pitch frame, from the focal point C_w.
        """
        uv_px = check_points(uv_px, 2, "uv_px")
        xy_d = (uv_px - self.principal_point) / self.focal_px
        xy_n = undistort_normalized(xy_d, self.k1, self.extra_distortion)
        rays_c = np.concatenate([xy_n, np.ones((len(xy_n), 1))], axis=1)
        rays_w = rays_c @ self._R_cw  # R_cw^T applied to each row
        return rays_w / np.linalg.norm(rays_w, axis=1, keepdims=True)

    def ground_intersection(self, uv_px: np.ndarray, plane_z_m: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Intersect the viewing rays of pixels with the horizontal plane z = plane_z_m.

        Args:
            uv_px: (N, 2) pixels.
            plane_z_m: height of the plane (0 is the pitch; z points down).

        Returns:
            points_w: (N, 3) metres; NaN where the ray does not hit the plane in front of the camera.
            hits: (N,) bool.
        """
        rays_w = self.backproject(uv_px)
        with np.errstate(divide="ignore", invalid="ignore"):
            distance = (plane_z_m - self.position_m[2]) / rays_w[:, 2]
        hits = np.isfinite(distance) & (distance > 0)
        points_w = self.position_m + rays_w * np.where(hits, distance, np.nan)[:, None]
        return points_w, hits

    # ----------------------------------------------------------------- SoccerNet dicts

    def to_soccernet_dict(self, width_px: int | None = None, height_px: int | None = None) -> dict:
        """The SoccerNet camera JSON object, with intrinsics at the requested resolution.

        Args:
            width_px, height_px: resolution the file is meant for (default: the camera's own).
        """
        camera = self if width_px is None else self.rescaled(width_px, height_px or self.height_px)
        principal = camera.principal_point
        extra = camera.extra_distortion
        return {
            "pan_degrees": camera.pan_deg,
            "tilt_degrees": camera.tilt_deg,
            "roll_degrees": camera.roll_deg,
            "position_meters": [float(v) for v in camera.position_m],
            "x_focal_length": float(camera.focal_px),
            "y_focal_length": float(camera.focal_px),
            "principal_point": [float(principal[0]), float(principal[1])],
            "radial_distortion": [float(camera.k1), *map(float, extra.radial_k2_k6)],
            "tangential_distortion": [float(v) for v in extra.tangential_p1_p2],
            "thin_prism_distortion": [float(v) for v in extra.thin_prism_s1_s4],
            "rotation_matrix": camera.R_cw.tolist(),
        }

    @classmethod
    def from_soccernet_dict(cls, data: dict, width_px: int | None = None, height_px: int | None = None) -> "Camera":
        """Camera from a SoccerNet camera JSON object.

        The file's own resolution is taken as twice its principal point (SoccerNet's
        rule); the camera is rescaled to (width_px, height_px) when given. Every field of
        the format is read; ``x_focal_length`` and ``y_focal_length`` are averaged if they
        differ (square pixels).

        Raises:
            ValueError: a field is missing, has the wrong length or is not finite.
        """
        def numbers(key: str, length: int | None, default=None) -> list[float]:
            if key not in data:
                if default is not None:
                    return list(default)
                raise ValueError(f"missing field '{key}'")
            value = data[key]
            values = list(value) if isinstance(value, (list, tuple)) else [value]
            if length is not None and len(values) != length:
                raise ValueError(f"field '{key}' has {len(values)} values, expected {length}")
            try:
                floats = [float(v) for v in values]
            except (TypeError, ValueError):
                raise ValueError(f"field '{key}' is not numeric: {value!r}") from None
            if not all(math.isfinite(v) for v in floats):
                raise ValueError(f"field '{key}' is not finite: {value!r}")
            return floats

        (pan,) = numbers("pan_degrees", 1)
        (tilt,) = numbers("tilt_degrees", 1)
        (roll,) = numbers("roll_degrees", 1)
        position = numbers("position_meters", 3)
        (fx,) = numbers("x_focal_length", 1)
        (fy,) = numbers("y_focal_length", 1, default=[fx])
        principal = numbers("principal_point", 2)
        radial = numbers("radial_distortion", None, default=[0.0] * 6)
        radial = (radial + [0.0] * 6)[:6]
        tangential = numbers("tangential_distortion", 2, default=[0.0, 0.0])
        prism = numbers("thin_prism_distortion", 4, default=[0.0] * 4)
        if principal[0] <= 0 or principal[1] <= 0:
            raise ValueError(f"principal_point must be positive, got {principal}")
        file_width = int(round(2 * principal[0]))
        file_height = int(round(2 * principal[1]))
        centred = abs(2 * principal[0] - file_width) < 1e-9 and abs(2 * principal[1] - file_height) < 1e-9
        camera = cls.from_degrees(
            0.5 * (fx + fy), radial[0], pan, tilt, roll, position, file_width, file_height,
            extra_distortion=ExtraDistortion(tuple(radial[1:6]), tuple(tangential), tuple(prism)),
            principal_point_px=None if centred else (principal[0], principal[1]),
        )
        if width_px is not None:
            camera = camera.rescaled(width_px, height_px if height_px is not None else round(file_height * width_px / file_width))
        return camera
