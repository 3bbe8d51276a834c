"""The soccer pitch template: the 26 SoccerNet marking classes as 3D elements.

Frame (SoccerNet convention): origin at the centre spot, x towards the right goal, y towards
the near touchline ("Side line bottom" is y = +W/2), z down (crossbars at z = -2.44).
Dimensions are parameters; the default is the 105 x 68 m pitch of SoccerNet.

Two samplings are offered:

* :meth:`PitchTemplate.sample_soccernet` reproduces, point for point, the sampling
  of the official SoccerNet camera evaluation (lines every ``step_line_m`` starting
  at the first extremity, circles every ``step_circle_m`` of arc, the centre circle
  left open by one step), so the evaluator matches the official numbers.
* :meth:`PitchTemplate.sample_uniform` spreads points evenly including both ends,
  for rendering, factors and masks.

This module does no I/O.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

LINE_CLASSES: tuple[str, ...] = (
    "Big rect. left bottom",
    "Big rect. left main",
    "Big rect. left top",
    "Big rect. right bottom",
    "Big rect. right main",
    "Big rect. right top",
    "Circle central",
    "Circle left",
    "Circle right",
    "Goal left crossbar",
    "Goal left post left",
    "Goal left post right",
    "Goal right crossbar",
    "Goal right post left",
    "Goal right post right",
    "Middle line",
    "Side line bottom",
    "Side line left",
    "Side line right",
    "Side line top",
    "Small rect. left bottom",
    "Small rect. left main",
    "Small rect. left top",
    "Small rect. right bottom",
    "Small rect. right main",
    "Small rect. right top",
)
"""The 26 pitch marking classes (names stripped of SoccerNet's trailing space)."""

UNKNOWN_CLASSES: tuple[str, ...] = ("Line unknown", "Goal unknown")
"""Annotation classes with no 3D element: never projected, so always a miss when annotated."""

ALL_ANNOTATION_CLASSES: tuple[str, ...] = LINE_CLASSES + UNKNOWN_CLASSES

GOAL_CLASSES: tuple[str, ...] = tuple(name for name in LINE_CLASSES if name.startswith("Goal"))
CIRCLE_CLASSES: tuple[str, ...] = ("Circle central", "Circle left", "Circle right")
OUTER_LINES: tuple[str, ...] = ("Side line bottom", "Side line left", "Side line right", "Side line top")
"""The touchlines and goal lines: the pitch's outline, every other marking inside it."""


def _mirror_name(name: str) -> str:
    """Class seen through the point reflection about the centre spot, (x, y) -> (-x, -y).

    Lines and areas swap left<->right and top<->bottom together. A goal swaps ends but
    its posts keep their names: the template names a post by its side as seen from
    that goal's end of the pitch (the left goal's "post left" is at y = +3.66, the right
    goal's "post left" at y = -3.66), so the reflection takes "Goal left post left" to
    "Goal right post left" (the official SoccerNet mirror table agrees).
    """
    if name in ("Middle line", "Circle central") or name in UNKNOWN_CLASSES:
        return name
    if name.startswith("Goal"):
        words = name.split(" ")
        words[1] = {"left": "right", "right": "left"}[words[1]]  # only the goal's end swaps
        return " ".join(words)
    swaps = {"left": "right", "right": "left", "top": "bottom", "bottom": "top"}
    return " ".join(swaps.get(word, word) for word in name.split(" "))


MIRRORED_CLASS: dict[str, str] = {name: _mirror_name(name) for name in ALL_ANNOTATION_CLASSES}
"""Class name -> class name under the point reflection through the pitch centre."""


@dataclass(frozen=True)
class PitchDimensions:
    """Pitch dimensions in metres (FIFA defaults, as in SoccerNet)."""

    length_m: float = 105.0  # goal line to goal line
    width_m: float = 68.0  # touchline to touchline
    centre_circle_radius_m: float = 9.15  # also the penalty arc radius
    penalty_area_depth_m: float = 16.5
    penalty_area_width_m: float = 40.32
    goal_area_depth_m: float = 5.5
    goal_area_width_m: float = 18.32
    penalty_mark_distance_m: float = 11.0  # from the goal line
    goal_width_m: float = 7.32  # between the posts
    goal_height_m: float = 2.44  # crossbar height

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"PitchDimensions.{name} must be a positive number, got {value!r}")
        if self.penalty_area_width_m >= self.width_m or self.penalty_area_depth_m * 2 >= self.length_m:
            raise ValueError("penalty area does not fit in the pitch")


@dataclass(frozen=True)
class Segment:
    """A straight marking from start_w to end_w (metres, pitch frame)."""

    start_w: tuple[float, float, float]
    end_w: tuple[float, float, float]

    @property
    def length_m(self) -> float:
        return float(np.linalg.norm(np.subtract(self.end_w, self.start_w)))

    def points_at(self, fractions: np.ndarray) -> np.ndarray:
        """(N,) fractions in [0, 1] -> (N, 3) points."""
        start = np.asarray(self.start_w, dtype=float)
        return start + np.asarray(fractions, dtype=float)[:, None] * (np.asarray(self.end_w, dtype=float) - start)


@dataclass(frozen=True)
class Arc:
    """A circle arc on the ground (z = 0) from from_rad to to_rad, counter-clockwise in (x, y)."""

    centre_w: tuple[float, float, float]
    radius_m: float
    from_rad: float
    to_rad: float

    @property
    def length_m(self) -> float:
        return self.radius_m * (self.to_rad - self.from_rad)

    @property
    def is_full_circle(self) -> bool:
        return self.to_rad - self.from_rad >= 2 * math.pi - 1e-12

    def points_at_angles(self, angles_rad: np.ndarray) -> np.ndarray:
        """(N,) angles -> (N, 3) points on the circle."""
        angles = np.asarray(angles_rad, dtype=float)
        cx, cy, cz = self.centre_w
        return np.stack(
            [cx + self.radius_m * np.cos(angles), cy + self.radius_m * np.sin(angles), np.full_like(angles, cz)], axis=1
        )

    def points_at(self, fractions: np.ndarray) -> np.ndarray:
        """(N,) fractions in [0, 1] of the arc -> (N, 3) points."""
        return self.points_at_angles(self.from_rad + np.asarray(fractions, dtype=float) * (self.to_rad - self.from_rad))


Element = Segment | Arc


class PitchTemplate:
    """The 3D pitch: one element per SoccerNet class, keypoints and samplings.

    Args:
        dimensions: pitch dimensions (default 105 x 68 m).
    """

    def __init__(self, dimensions: PitchDimensions | None = None) -> None:
        self.dimensions = dimensions or PitchDimensions()
        self.elements: dict[str, Element] = self._build_elements()

    # ----------------------------------------------------------------- geometry

    def _build_elements(self) -> dict[str, Element]:
        d = self.dimensions
        half_l, half_w = d.length_m / 2, d.width_m / 2
        pa_x, pa_y = half_l - d.penalty_area_depth_m, d.penalty_area_width_m / 2
        ga_x, ga_y = half_l - d.goal_area_depth_m, d.goal_area_width_m / 2
        post_y, bar_z = d.goal_width_m / 2, -d.goal_height_m
        mark_x = half_l - d.penalty_mark_distance_m
        radius = d.centre_circle_radius_m
        # Angle at the penalty mark where the arc meets the penalty-area line.
        arc_dx = d.penalty_area_depth_m - d.penalty_mark_distance_m
        if arc_dx >= radius:
            raise ValueError("penalty arc does not reach outside the penalty area")
        arc_half = math.acos(arc_dx / radius)

        def seg(a, b) -> Segment:
            return Segment(tuple(map(float, a)), tuple(map(float, b)))

        # Extremity order follows SoccerNet's template so that sampled polylines run the same way.
        return {
            "Big rect. left bottom": seg((-half_l, pa_y, 0), (-pa_x, pa_y, 0)),
            "Big rect. left main": seg((-pa_x, -pa_y, 0), (-pa_x, pa_y, 0)),
            "Big rect. left top": seg((-half_l, -pa_y, 0), (-pa_x, -pa_y, 0)),
            "Big rect. right bottom": seg((pa_x, pa_y, 0), (half_l, pa_y, 0)),
            "Big rect. right main": seg((pa_x, -pa_y, 0), (pa_x, pa_y, 0)),
            "Big rect. right top": seg((pa_x, -pa_y, 0), (half_l, -pa_y, 0)),
            "Circle central": Arc((0.0, 0.0, 0.0), radius, 0.0, 2 * math.pi),
            # Left arc: centred on the left mark, facing +x, from its top (-y) end to its bottom end.
            "Circle left": Arc((-mark_x, 0.0, 0.0), radius, 2 * math.pi - arc_half, 2 * math.pi + arc_half),
            # Right arc: centred on the right mark, facing -x, from its bottom (+y) end to its top end.
            "Circle right": Arc((mark_x, 0.0, 0.0), radius, 2 * math.pi + math.pi - arc_half, 2 * math.pi + math.pi + arc_half),
            "Goal left crossbar": seg((-half_l, -post_y, bar_z), (-half_l, post_y, bar_z)),
            "Goal left post left": seg((-half_l, post_y, bar_z), (-half_l, post_y, 0)),
            "Goal left post right": seg((-half_l, -post_y, bar_z), (-half_l, -post_y, 0)),
            "Goal right crossbar": seg((half_l, -post_y, bar_z), (half_l, post_y, bar_z)),
            "Goal right post left": seg((half_l, -post_y, bar_z), (half_l, -post_y, 0)),
            "Goal right post right": seg((half_l, post_y, bar_z), (half_l, post_y, 0)),
            "Middle line": seg((0, -half_w, 0), (0, half_w, 0)),
            "Side line bottom": seg((-half_l, half_w, 0), (half_l, half_w, 0)),
            "Side line left": seg((-half_l, -half_w, 0), (-half_l, half_w, 0)),
            "Side line right": seg((half_l, -half_w, 0), (half_l, half_w, 0)),
            "Side line top": seg((-half_l, -half_w, 0), (half_l, -half_w, 0)),
            "Small rect. left bottom": seg((-half_l, ga_y, 0), (-ga_x, ga_y, 0)),
            "Small rect. left main": seg((-ga_x, -ga_y, 0), (-ga_x, ga_y, 0)),
            "Small rect. left top": seg((-half_l, -ga_y, 0), (-ga_x, -ga_y, 0)),
            "Small rect. right bottom": seg((ga_x, ga_y, 0), (half_l, ga_y, 0)),
            "Small rect. right main": seg((ga_x, -ga_y, 0), (ga_x, ga_y, 0)),
            "Small rect. right top": seg((ga_x, -ga_y, 0), (half_l, -ga_y, 0)),
        }

    @property
    def outline_w(self) -> np.ndarray:
        """(4, 3) pitch corners, counter-clockwise from top-left (-x, -y), z = 0."""
        half_l, half_w = self.dimensions.length_m / 2, self.dimensions.width_m / 2
        return np.array([[-half_l, -half_w, 0.0], [half_l, -half_w, 0.0], [half_l, half_w, 0.0], [-half_l, half_w, 0.0]])

    def is_on_ground(self, name: str) -> bool:
        """True for the markings painted on the grass (not goal posts or crossbars)."""
        return not name.startswith("Goal")

    # ----------------------------------------------------------------- sampling

    def sample_uniform(self, step_m: float = 0.25, classes=None) -> dict[str, np.ndarray]:
        """Evenly spaced points on every element, both ends included.

        Args:
            step_m: largest spacing between consecutive points, metres.
            classes: iterable of class names (default: all 26).

        Returns:
            class name -> (N, 3) points in metres, in the element's direction.
        """
        if step_m <= 0:
            raise ValueError(f"step_m must be positive, got {step_m}")
        out = {}
        for name in classes or LINE_CLASSES:
            element = self.elements[name]
            count = max(2, int(math.ceil(element.length_m / step_m)) + 1)
            fractions = np.linspace(0.0, 1.0, count)
            if isinstance(element, Arc) and element.is_full_circle:
                fractions = np.linspace(0.0, 1.0, count)  # closed: last point repeats the first
            out[name] = element.points_at(fractions)
        return out

    def sample_soccernet(self, step_line_m: float = 0.9, step_circle_m: float = 0.2) -> dict[str, np.ndarray]:
        """The sampling of the official SoccerNet camera evaluation, point for point.

        Lines: the first extremity, then ``int(length / step - 1)`` points spaced
        ``step_line_m`` apart, then the second extremity. Penalty arcs: the first end,
        ``int(arc_length / step_circle_m)`` points spaced ``step_circle_m`` of arc, then the
        last end. Centre circle: ``int(circumference / step_circle_m)`` points from angle
        0, not closed.

        Returns:
            class name -> (N, 3) points in metres.
        """
        out = {}
        for name in LINE_CLASSES:
            element = self.elements[name]
            if isinstance(element, Segment):
                start = np.asarray(element.start_w, dtype=float)
                end = np.asarray(element.end_w, dtype=float)
                length = float(np.linalg.norm(end - start))
                count = int(length / step_line_m - 1)
                direction = (end - start) / length
                steps = np.arange(1, count + 1, dtype=float)[:, None] * step_line_m
                out[name] = np.vstack([start, start + steps * direction, end])
            elif element.is_full_circle:
                count = int(element.length_m / step_circle_m)
                angles = element.from_rad + np.arange(count) * (step_circle_m / element.radius_m)
                out[name] = element.points_at_angles(angles)
            else:
                count = int(element.length_m / step_circle_m)
                angles = element.from_rad + np.arange(1, count + 1) * (step_circle_m / element.radius_m)
                ends = element.points_at_angles(np.array([element.from_rad, element.to_rad]))
                out[name] = np.vstack([ends[:1], element.points_at_angles(angles), ends[1:]])
        return out

    # ----------------------------------------------------------------- keypoints

    @cached_property
    def keypoints(self) -> dict[str, np.ndarray]:
        """Named 3D keypoints (metres): line intersections, line/circle intersections,
        penalty marks, centre spot, post feet and tops.

        Names: ``"A | B"`` for the meeting point of classes A and B (in LINE_CLASSES
        order), ``"A | B (top)"``/``"(bottom)"`` where they meet twice, plus
        ``"Centre spot"``, ``"Left penalty mark"``, ``"Right penalty mark"``,
        ``"Centre circle left"``/``"right"`` (on the x axis) and the goal post feet and tops
        ``"Goal left post left (foot)"``, ``"... (top)"``.
        """
        d = self.dimensions
        points: dict[str, np.ndarray] = {
            "Centre spot": np.zeros(3),
            "Left penalty mark": np.array([-(d.length_m / 2 - d.penalty_mark_distance_m), 0.0, 0.0]),
            "Right penalty mark": np.array([d.length_m / 2 - d.penalty_mark_distance_m, 0.0, 0.0]),
            "Centre circle left": np.array([-d.centre_circle_radius_m, 0.0, 0.0]),
            "Centre circle right": np.array([d.centre_circle_radius_m, 0.0, 0.0]),
        }
        ground_segments = {
            name: el for name, el in self.elements.items() if isinstance(el, Segment) and self.is_on_ground(name)
        }
        for (name_a, seg_a), (name_b, seg_b) in itertools.combinations(ground_segments.items(), 2):
            hit = _segment_intersection_2d(seg_a, seg_b)
            if hit is not None:
                points[f"{name_a} | {name_b}"] = np.array([hit[0], hit[1], 0.0])
        for arc_name in CIRCLE_CLASSES:
            arc = self.elements[arc_name]
            for seg_name, seg in ground_segments.items():
                hits = _arc_segment_intersections_2d(arc, seg)
                hits.sort(key=lambda p: p[1])  # top (-y) first
                for label, hit in zip(("top", "bottom"), hits):
                    suffix = f" ({label})" if len(hits) > 1 else ""
                    points[f"{seg_name} | {arc_name}{suffix}"] = np.array([hit[0], hit[1], 0.0])
        for name in GOAL_CLASSES:
            if "post" in name:
                seg = self.elements[name]
                points[f"{name} (top)"] = np.asarray(seg.start_w, dtype=float)
                points[f"{name} (foot)"] = np.asarray(seg.end_w, dtype=float)
        return points

    def keypoint_array(self, names) -> np.ndarray:
        """(N, 3) positions of the named keypoints; KeyError names an unknown one."""
        table = self.keypoints
        missing = [n for n in names if n not in table]
        if missing:
            raise KeyError(f"unknown pitch keypoint(s): {missing}")
        return np.array([table[n] for n in names], dtype=float).reshape(-1, 3)


def _segment_intersection_2d(a: Segment, b: Segment, tol: float = 1e-6):
    p, r = np.asarray(a.start_w[:2]), np.subtract(a.end_w[:2], a.start_w[:2])
    q, s = np.asarray(b.start_w[:2]), np.subtract(b.end_w[:2], b.start_w[:2])
    denom = r[0] * s[1] - r[1] * s[0]
    if abs(denom) < 1e-12:
        return None
    qp = q - p
    t = (qp[0] * s[1] - qp[1] * s[0]) / denom
    u = (qp[0] * r[1] - qp[1] * r[0]) / denom
    if -tol <= t <= 1 + tol and -tol <= u <= 1 + tol:
        return p + t * r
    return None


def _arc_segment_intersections_2d(arc: Arc, seg: Segment, tol: float = 1e-6) -> list:
    p = np.asarray(seg.start_w[:2], dtype=float)
    r = np.subtract(seg.end_w[:2], seg.start_w[:2])
    c = np.asarray(arc.centre_w[:2], dtype=float)
    f = p - c
    a_ = r @ r
    b_ = 2 * f @ r
    c_ = f @ f - arc.radius_m**2
    disc = b_ * b_ - 4 * a_ * c_
    if disc < 0:
        return []
    hits = []
    for t in sorted({(-b_ - math.sqrt(disc)) / (2 * a_), (-b_ + math.sqrt(disc)) / (2 * a_)}):
        if -tol <= t <= 1 + tol:
            point = p + t * r
            angle = math.atan2(point[1] - c[1], point[0] - c[0])
            # Bring the angle into the arc's range.
            while angle < arc.from_rad - 1e-9:
                angle += 2 * math.pi
            if arc.is_full_circle or angle <= arc.to_rad + 1e-9:
                hits.append(point)
    return hits
