"""Which broadcast camera a fitted camera belongs to: one id per tripod, kept when the camera returns.

A broadcast cuts between several tripod cameras. Each camera found gets an id: the id of a
known camera whose tripod (or, before its tripod is fitted, its first confident focal point)
stands where the new camera stands, else a new id named after its kind
(:func:`broadtrack_graph.reinit.positions.camera_kind`): ``main`` for the first main camera,
``high-behind-1``, ``high-corner-1``, ... for the others. A new id is provisional until its camera
has a trusted frame or a tripod: the tracker forgets it at the next cut otherwise. The last trusted camera of each id
is that id's guess when the tracker is lost or a shot begins (:meth:`CameraRegistry.guesses`). No I/O.

"Where it stands" is judged along and across the new camera's line of sight apart. A camera
fitted from one frame is uncertain mostly along its optical axis: moving the focal point
towards the pitch while widening the focal length changes the view little (a main camera
re-initialised on one shot moves 10 m along its line of sight, a few tenths of a metre across
it). Across the line of sight the view changes (the parallax between the near and far
touchlines), so two cameras a few metres apart across it are two cameras, each with its own
tripod, even on one gantry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.positions import MAIN_KIND, camera_kind

ON_TRIPOD_M = 1.0
"""A focal point within this of a known camera's position stands on its tripod (the focal point moves by the tripod's
offset, 0.2-0.5 m, with the zoom; a search at a known camera's position holds it there)."""


@dataclass(frozen=True)
class Guess:
    """A known camera's guess for a frame: the camera id it continues, where it comes from, and the Camera."""

    camera_id: str
    label: str
    camera: Camera


class CameraRegistry:
    """The cameras of a run by id, the focal point that identifies each, and each one's last trusted camera.

    Args:
        same_camera_m: without a line of sight, a focal point this close to a known camera's position is
            that camera.
        along_sight_m, across_sight_m: with a line of sight, a focal point this close to a known camera's
            position along it and across it is that camera (module docstring). The focal point slides along
            the optical axis with zoom (a few tenths of a metre) and a re-initialised camera can sit ten
            metres off along its line of sight; across it, a few metres already change the view.
        known: camera id -> position (metres, pitch frame), e.g. the tripods given to the run.
    """

    def __init__(self, same_camera_m: float = 8.0, along_sight_m: float = 12.0, across_sight_m: float = 4.0,
                 known: dict[str, np.ndarray] | None = None) -> None:
        self.same_camera_m = float(same_camera_m)
        self.along_sight_m = float(along_sight_m)
        self.across_sight_m = float(across_sight_m)
        self.positions: dict[str, np.ndarray] = {k: np.asarray(v, float).reshape(3) for k, v in (known or {}).items()}
        self.untrusted: set[str] = set()  # new ids whose camera has had no trusted frame (nor a tripod) yet
        self.last_confident: dict[str, tuple[int, object]] = {}  # camera id -> (frame index, Camera)
        self._counts: dict[str, int] = {}

    def identify(self, position_w, sight_w=None, fits=None, along_share: float = 0.0) -> str:
        """The id of the camera standing at position_w (a new id when no known camera is there).

        sight_w: (3,) the camera's optical axis in the pitch frame (``Camera.R_cw[2]``), or None to
        judge by distance alone.
        fits: ``camera id -> bool``, whether the frame is explained as well by a camera at that known camera's
        position (None: standing there is enough). A camera that stands near a known one but whose view the known
        tripod does not explain (another stadium's camera at a similar place) gets a new id.
        along_share: with ``fits``, when no known camera stands there, one off along the line of sight by up to this
        share of the distance to where the line meets the ground is tried too (a narrow view's markings fix its
        distance loosely: whether the frame is explained from there decides).
        """
        p = np.asarray(position_w, float).reshape(3)
        nearest = self.nearest(p, sight_w)
        if nearest is None and fits is not None and sight_w is not None and along_share > 0.0:
            axis = np.asarray(sight_w, float).reshape(3) / np.linalg.norm(sight_w)
            if axis[2] > 1e-9 and p[2] < 0.0:  # its distance to where its line of sight meets the ground
                nearest = self.nearest(p, sight_w, along_m=max(self.along_sight_m, along_share * -p[2] / axis[2]))
        if nearest is not None and fits is not None and not fits(nearest):
            nearest = None
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
        self.untrusted.add(camera_id)
        return camera_id

    def nearest(self, position_w, sight_w=None, along_m: float | None = None) -> str | None:
        """The nearest known camera standing where position_w is (see :meth:`identify`; ``along_m``: the reach along
        the line of sight, default ``along_sight_m``), or None."""
        p = np.asarray(position_w, float).reshape(3)
        best, best_d = None, math.inf
        for camera_id, q in self.positions.items():
            if not self.same_place(q, p, sight_w, along_m):
                continue
            d = float(np.linalg.norm(p - q))
            if d <= best_d:
                best, best_d = camera_id, d
        return best

    def stands_at(self, camera_id: str, position_w, sight_w=None) -> bool:
        """True when a camera at position_w (looking along sight_w) can be the known camera ``camera_id``."""
        return self.same_place(self.positions[camera_id], position_w, sight_w)

    def on_tripod(self, camera_id: str, position_w) -> bool:
        """True when a focal point at position_w stands on the known camera ``camera_id``'s tripod (within
        ``ON_TRIPOD_M`` of its position): its focal point, not only its place."""
        known = self.positions.get(camera_id)
        return known is not None and float(np.linalg.norm(np.asarray(position_w, float).reshape(3) - known)) <= \
            ON_TRIPOD_M

    def same_place(self, known_w, position_w, sight_w=None, along_m: float | None = None) -> bool:
        """True when a camera at position_w (looking along sight_w) can stand where one at known_w stands: within
        ``along_m`` (default ``along_sight_m``) along its line of sight and ``across_sight_m`` across it
        (``same_camera_m`` without a sight)."""
        offset = np.asarray(position_w, float).reshape(3) - np.asarray(known_w, float).reshape(3)
        if sight_w is None:
            return float(np.linalg.norm(offset)) <= self.same_camera_m
        axis = np.asarray(sight_w, float).reshape(3)
        axis = axis / np.linalg.norm(axis)
        along = float(offset @ axis)
        across = float(np.linalg.norm(offset - along * axis))
        return abs(along) <= (self.along_sight_m if along_m is None else along_m) and across <= self.across_sight_m

    def update(self, camera_id: str, position_w) -> None:
        """A better position for a known camera (its fitted tripod): the camera is trusted."""
        self.positions[camera_id] = np.asarray(position_w, float).reshape(3)
        self.untrusted.discard(camera_id)

    def trust(self, camera_id: str, frame_index: int, camera) -> None:
        """The camera had a trusted frame (its Camera): its id is kept, and it is the id's guess from now on."""
        self.untrusted.discard(camera_id)
        self.last_confident[camera_id] = (frame_index, camera)

    def guesses(self, frame_index: int, camera_id: str | None, max_age_frames: int) -> list[Guess]:
        """The guesses for a frame: the last confident camera of ``camera_id`` (None: of every
        camera), seen at most ``max_age_frames`` before, and the same camera moved to its id's known position."""
        out = []
        for guess_id in [camera_id] if camera_id is not None else list(self.last_confident):
            if guess_id not in self.last_confident:
                continue
            seen, camera = self.last_confident[guess_id]
            if not 0 <= frame_index - seen <= max_age_frames:
                continue
            out.append(Guess(guess_id, f"last confident camera of {guess_id} (frame {seen})", camera))
            known = self.positions.get(guess_id)
            if known is not None and np.linalg.norm(known - camera.position_m) > 0.5:
                out.append(Guess(guess_id, f"last confident camera of {guess_id} (frame {seen}) at its tripod",
                                 camera.replace(position_m=known)))
        return out

    def forget_untrusted(self) -> None:
        """Forget the ids whose camera was never trusted (a wrong camera of a shot's first frame may stand there)."""
        for camera_id in self.untrusted:
            self.positions.pop(camera_id, None)
        self.untrusted.clear()
