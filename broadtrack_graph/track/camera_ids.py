"""Which broadcast camera a fitted camera belongs to: one id per tripod, kept when the camera returns.

A broadcast cuts between several tripod cameras. Each camera found gets an id: the id of a
known camera whose tripod (or, before its tripod is fitted, its first confident focal point)
lies within ``same_camera_m`` of the new focal point, else a new id named after its kind
(:func:`broadtrack_graph.reinit.positions.camera_kind`): ``main`` for the first main camera,
``high-behind-1``, ``high-corner-1``, ... for the others. No I/O.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.reinit.positions import MAIN_KIND, camera_kind


class CameraRegistry:
    """The cameras of a run by id, and the focal point that identifies each.

    Args:
        same_camera_m: a focal point this close to a known camera's position is that camera. The
            focal point slides along the optical axis with zoom (a few tenths of a metre) and a
            re-initialised camera can sit a few metres off along its line of sight; two cameras of
            a broadcast stand ten metres or more apart.
        known: camera id -> position (metres, pitch frame), e.g. the tripods given to the run.
    """

    def __init__(self, same_camera_m: float = 8.0, known: dict[str, np.ndarray] | None = None) -> None:
        self.same_camera_m = float(same_camera_m)
        self.positions: dict[str, np.ndarray] = {k: np.asarray(v, float).reshape(3) for k, v in (known or {}).items()}
        self._counts: dict[str, int] = {}

    def identify(self, position_w) -> str:
        """The id of the camera standing at position_w (a new id when no known camera is near)."""
        p = np.asarray(position_w, float).reshape(3)
        nearest = self.nearest(p)
        if nearest is not None:
            return nearest
        kind, _ = camera_kind(p)
        if kind == MAIN_KIND and MAIN_KIND not in self.positions:
            camera_id = MAIN_KIND
        else:
            self._counts[kind] = self._counts.get(kind, 0) + 1
            camera_id = f"{kind}-{self._counts[kind]}"
            while camera_id in self.positions:
                self._counts[kind] += 1
                camera_id = f"{kind}-{self._counts[kind]}"
        self.positions[camera_id] = p
        return camera_id

    def nearest(self, position_w) -> str | None:
        """The known camera within ``same_camera_m`` of position_w, nearest first, or None."""
        p = np.asarray(position_w, float).reshape(3)
        best, best_d = None, self.same_camera_m
        for camera_id, q in self.positions.items():
            d = float(np.linalg.norm(p - q))
            if d <= best_d:
                best, best_d = camera_id, d
        return best

    def update(self, camera_id: str, position_w) -> None:
        """A better position for a known camera (its fitted tripod)."""
        self.positions[camera_id] = np.asarray(position_w, float).reshape(3)
