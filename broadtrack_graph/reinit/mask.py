"""Weight-free re-initialisation: a camera from the unlabelled marking map alone.

:func:`reinit_from_mask` builds camera hypotheses from the structure of the map at each
candidate tripod position (two straight markings put on two pitch lines, :mod:`.line_pairs`;
a pitch circle put on an ellipse of the map, :mod:`.ellipses`; scale-free, so tight zooms are
found as well as wide views), scores each against the map and the marking points
(:mod:`.map_score`), and fits the best few after naming the map's points by the projected
template (:func:`label_points_by_camera`).

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y. No I/O.
"""

from __future__ import annotations

import hashlib
import logging
import math
from dataclasses import dataclass, replace

import numpy as np

from broadtrack_graph.detect.ellipse_refit import refitted_ellipse, same_ellipse
from broadtrack_graph.detect.marking_arcs import marking_arcs
from broadtrack_graph.detect.marking_ellipses import marking_ellipses_both
from broadtrack_graph.detect.marking_structures import marking_lines
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.point_windows import PointWindows
from broadtrack_graph.geometry.template import TemplateCurves, to_segments
from broadtrack_graph.reinit.confidence import camera_confidence
from broadtrack_graph.reinit.ellipses import circle_hypotheses
from broadtrack_graph.reinit.line_pairs import line_pair_hypotheses, pitch_lines
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.map_score import Hypothesis, MapScorer, best_distinct, polish_locally
from broadtrack_graph.reinit.mask_config import MaskSearchConfig, RefineSchedule
from broadtrack_graph.reinit.positions import DEFAULT_TRIPOD_POSITIONS_W
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class _BestFit:
    """The search's best fit so far: its score on the map (-cost: higher is better), the camera, the focal point
    its hypothesis stood at (metres), and whether it came from the first hypothesis fitted."""

    score: float
    camera: Camera
    position_w: np.ndarray
    first: bool


def reinit_from_mask(
    marking_mask: np.ndarray,
    marking_points_px: np.ndarray,
    frame_size: tuple[int, int],
    pitch: PitchTemplate | None = None,
    positions_w=None,
    config: MaskSearchConfig = MaskSearchConfig(),
    curves: TemplateCurves | None = None,
    field_mask: np.ndarray | None = None,
) -> ReinitResult:
    """Weight-free re-initialisation: camera hypotheses from the structure of the marking map, scored, then fitted.

    1. Hypotheses (roll 0, k1 0) at each candidate focal point (default: the default tripods, not
       mirrored: the map has no labels and the pitch is symmetric): pairs of straight markings
       put on pairs of pitch lines (:func:`marking_lines`, :func:`line_pair_cameras`; any zoom,
       f from a grid then moved along each pair's family), and a pitch circle put on an ellipse
       of the map (:func:`marking_ellipses`, :func:`ellipse_cameras`; the centre circle alone).
       When nothing scores ``poor_score`` at the default tripods, ``far_positions_w`` (main
       cameras further back and higher) are tried, and circle arcs at the image border too
       (``marking_ellipses(at_border=True)``).
    2. Every hypothesis gets one score, -F_beta of the template found in the map (recall) and the
       marking points explained by the template (precision, through the pitch plane)
       (:class:`MapScorer`); the first candidate position is preferred on near ties. When none
       scores ``poor_score`` (made at a wrong focal point, a right hypothesis can sit 10-30 px off
       and score below a wrong one), the best distinct ones are moved to the nearby pan, tilt and
       f the map scores best (:func:`polish_locally`).
    3. The best distinct hypotheses are fitted in turn (:func:`refine_on_map`: name the marking
       points by the nearest projected class, :func:`fit_camera_to_lines`, shrinking gate; the
       wide schedule as well on poorly scoring ones) and ranked by a fine fit score; the
       best-scoring hypothesis is kept unless a later one fits ``fit_switch_margin`` better.

    The returned score is the confidence of the camera (``score.jaccard``,
    confidence.camera_confidence). One search: which positions to try next when its camera is not
    confident is the tracker's decision (:mod:`broadtrack_graph.track.reinit_policy`).

    Args:
        marking_mask: bool marking map (frame size or a reduced size of the same aspect ratio).
        marking_points_px: (M, 2) centre-line points, frame pixels.
        frame_size: (W, H) of the frame (the camera's resolution).
        positions_w: candidate focal points (metres); None = :data:`DEFAULT_TRIPOD_POSITIONS_W` (and the
            far positions when they fit poorly).
        field_mask: optional bool map of the playing surface (for the confidence).

    Returns:
        ReinitResult with the camera at frame_size, or camera None and a reason.
    """
    pitch = pitch or PitchTemplate()
    curves = curves or TemplateCurves(pitch)
    W, H = frame_size
    points_px = np.asarray(marking_points_px, float).reshape(-1, 2)
    if not marking_mask.any() or len(points_px) < 10:
        return ReinitResult(None, None, "", "too few marking pixels")
    positions = list(DEFAULT_TRIPOD_POSITIONS_W.values()) if positions_w is None else [tuple(p) for p in positions_w]
    ground = [n for n in pitch.elements if pitch.is_on_ground(n)]
    structures = map_structures(marking_mask, points_px, (W, H), pitch, config)
    scorer, lines = structures.scorer, structures.lines
    lines_w = pitch_lines(pitch)
    ratio = (config.line_focal_range_per_width[1] / config.line_focal_range_per_width[0]) ** (
        1.0 / max(config.line_focal_count - 1, 1))
    steps = ratio ** np.linspace(-1.0, 1.0, config.polish_focal_steps)
    hypotheses: list[Hypothesis] = []
    for position in positions:
        hypotheses += line_pair_hypotheses(lines, position, (W, H), pitch, lines_w, scorer, config, steps)
    if positions_w is None and (not hypotheses or -min(h.cost for h in hypotheses) < config.poor_score):
        # A poor fit at every guess: main cameras of larger stadiums stand further back and higher, on about
        # the same line of sight to the centre spot (the images along it differ mostly by f).
        for position in config.far_positions_w:
            hypotheses += line_pair_hypotheses(lines, position, (W, H), pitch, lines_w, scorer, config, steps)
    ellipses = structures.ellipses() if config.structures.max_ellipses else []
    if ellipses:
        hypotheses += circle_hypotheses(ellipses, points_px, positions, (W, H), pitch, curves, scorer, config)
    if config.structures.max_ellipses and (not hypotheses or -min(h.cost for h in hypotheses) < config.poor_score):
        # Nothing fits well: arcs at the image border (a tight zoom's centre circle) are tried too. Not
        # before: fitted to a short arc (or a penalty arc taken for the centre circle) they mislead.
        border = structures.border_ellipses()
        hypotheses += circle_hypotheses(border, points_px, positions, (W, H), pitch, curves, scorer, config)
        ellipses = ellipses + border
    if not hypotheses:
        return ReinitResult(None, None, "", "no hypothesis from the marking map")
    # The first candidate (the main camera by default) is the likelier one when scores are about equal.
    first = np.asarray(positions[0], float)
    weights = np.array([1.0 if np.allclose(h.position_w, first) else config.other_position_factor for h in hypotheses])
    if -min(h.cost for h in hypotheses) < config.poor_score:
        # Nothing explains the map well: the hypotheses were likely made at a wrong focal point.
        hypotheses = polish_locally(hypotheses, scorer, config, W, weights)
    costs = np.array([h.cost for h in hypotheses]) * weights
    angles_and_focals = (np.array([h.pan_rad for h in hypotheses]), np.array([h.tilt_rad for h in hypotheses]),
                         np.array([h.focal_px for h in hypotheses]))
    chosen = best_distinct(*angles_and_focals, costs, config.refine_top_k, config.distinct_per_width * W, W)
    log.debug("mask re-init: %d lines, %d ellipses, %d hypotheses", len(lines), len(ellipses), len(hypotheses))
    points = fit_points(points_px, config)
    fine = structures.fine_scorer
    check_w = np.vstack(list(pitch.sample_uniform(4.0, classes=ground).values()))
    best: _BestFit | None = None
    refined: list[Camera] = []

    def start_of(hypothesis: Hypothesis) -> Camera:
        return Camera(hypothesis.focal_px, 0.0, hypothesis.pan_rad, hypothesis.tilt_rad, 0.0, hypothesis.position_w,
                      W, H)

    def fit(start: Camera, wide: bool) -> None:
        nonlocal best
        C = start.position_m
        camera = refine_on_map(start, points, C, curves, config, config.schedule)
        refined.append(camera)
        score = -fine.camera_cost(camera, config.fit_hit_px, config.fit_point_px)
        if wide:
            # A poor fit at the guessed focal point: the camera may stand metres away, leaving the hypothesis
            # 10-20 px off, out of reach of the tight fit; one whose robust scale starts wide reaches it.
            wide_camera = refine_on_map(start, points, C, curves, config, config.wide_schedule)
            refined.append(wide_camera)
            wide_score = -fine.camera_cost(wide_camera, config.fit_hit_px, config.fit_point_px)
            if wide_score > score:
                camera, score = wide_camera, wide_score
        # The best-scoring hypothesis is kept unless a later one fits clearly better: on sparse or blurred
        # markings a fit can slide along the focal length / distance trade-off onto clutter, or push
        # undetected markings out of the image, and look a little better.
        if best is None or score > best.score + (config.fit_switch_margin if best.first else 0.0):
            best = _BestFit(score, camera, C, best is None)

    for k in chosen:
        hypothesis = hypotheses[k]
        if costs[k] > config.refine_cost_share * costs[chosen[0]] or len(refined) >= config.max_fits:
            break  # no close competitor of the best-scoring hypothesis left, or enough fits
        start = start_of(hypothesis)
        if any(_image_distance_px(start, other, check_w) < config.distinct_per_width * W for other in refined):
            continue  # a fit already landed here
        fit(start, config.wide_schedule is not None and -hypothesis.cost < config.wide_below_score
            and len(refined) + 1 < config.max_fits)
        if best.score >= config.accept_fit_score:
            break
    if best is None:
        return ReinitResult(None, None, "", "no hypothesis could be fitted", len(hypotheses))
    jac = camera_confidence(best.camera, marking_mask, curves, field_mask=field_mask)
    return ReinitResult(best.camera, LabelledScore(jac, 0, 0, 0, 0.0, 0.0),
                        f"mask search at {tuple(round(float(v)) for v in best.position_w)}", tried=len(hypotheses))


class MapStructures:
    """What a search takes from one marking map before any candidate position: the scorers, the straight
    markings and the ellipses (the border ones when asked). The stages of a search (several calls of
    :func:`reinit_from_mask` on one frame) share them: :func:`map_structures` keeps the last frame's."""

    def __init__(self, marking_mask: np.ndarray, points_px: np.ndarray, frame_size: tuple[int, int],
                 pitch: PitchTemplate, config: MaskSearchConfig):
        W = frame_size[0]
        self._mask, self._W, self._config, self.points_px = marking_mask, W, config, points_px
        self.scorer = MapScorer(marking_mask, points_px, frame_size, pitch, config)
        self.fine_scorer = MapScorer(marking_mask, points_px, frame_size, pitch,
                                     replace(config, score_template_step_m=config.fit_template_step_m,
                                             score_max_points=config.fit_max_points), same_map_as=self.scorer)
        self.lines = marking_lines(marking_mask, W, config.structures)
        self._ellipses: list | None = None
        self._border: list | None = None
        self._arcs: list | None = None
        self._refitted: list | None = None

    def ellipses(self) -> list:
        if self._ellipses is None:  # with the border ones: one fit of the pieces gives both
            self._ellipses, self._border = marking_ellipses_both(self._mask, self._W, self._config.structures,
                                                                 lines=self.lines)
        return self._ellipses

    def arcs(self) -> list:
        """Single curved pieces of the map as ellipses (a penalty arc:
        :func:`~broadtrack_graph.detect.marking_arcs.marking_arcs`)."""
        if self._arcs is None:
            self._arcs = marking_arcs(self._mask, self._W, self.lines, self._config.structures)
        return self._arcs

    def border_ellipses(self) -> list:
        self.ellipses()
        return self._border

    def every_ellipse(self) -> list:
        """The ellipses, whole then at the border, then the arcs: every image of a circle the map's pieces give."""
        return self.ellipses() + self.border_ellipses() + self.arcs()

    def refitted_ellipses(self) -> list:
        """The ellipses, whole and at the border, and the arcs fitted again on the markings' centre points near them,
        where that moves them (:func:`~broadtrack_graph.detect.ellipse_refit.refitted_ellipse`)."""
        if self._refitted is None:
            self._refitted = []
            for ellipse in self.every_ellipse():
                refit = refitted_ellipse(ellipse, self.points_px, self._W, self.lines)
                if refit is not None and not any(same_ellipse(refit, kept, self._W) for kept in self._refitted):
                    self._refitted.append(refit)  # fits from nearby ellipses end on the same one
        return self._refitted


_LAST_STRUCTURES: list = []  # [(key, pitch, MapStructures)] of the last frame searched


def map_structures(marking_mask, points_px, frame_size, pitch, config) -> MapStructures:
    """The :class:`MapStructures` of a map: the last frame's when the map, points, size and settings are the
    same."""
    digest = hashlib.blake2b(digest_size=16)
    for array in (np.ascontiguousarray(marking_mask), np.ascontiguousarray(points_px, float)):
        digest.update(str(array.shape).encode())
        digest.update(array.tobytes())
    key = (digest.digest(), tuple(frame_size), config)
    if _LAST_STRUCTURES and _LAST_STRUCTURES[0][0] == key and _LAST_STRUCTURES[0][1] is pitch:
        return _LAST_STRUCTURES[0][2]
    structures = MapStructures(marking_mask, points_px, frame_size, pitch, config)
    _LAST_STRUCTURES[:] = [(key, pitch, structures)]
    return structures


def fit_points(marking_points_px: np.ndarray, config: MaskSearchConfig) -> np.ndarray:
    """(M', 2) the marking points the label-and-fit rounds use: at most ``config.max_fit_points``, evenly subsampled."""
    points = np.asarray(marking_points_px, float).reshape(-1, 2)
    if len(points) > config.max_fit_points:
        points = points[np.linspace(0, len(points) - 1, config.max_fit_points).astype(int)]
    return points


def refine_on_map(camera: Camera, points_px: np.ndarray, position_w, curves: TemplateCurves,
                   config: MaskSearchConfig, schedule: RefineSchedule, hold_position: bool = False) -> Camera:
    """Label-and-fit rounds with a shrinking gate and a robust scale tied to it (:class:`RefineSchedule`);
    ``hold_position``: the focal point held where ``camera`` has it (f, k1 and the angles fitted)."""
    W = camera.width_px
    base = LineFitConfig(polish_power=0.0, iterations=schedule.iterations, sigma_position_m=config.position_sigma_m,
                         sigma_k1=config.sigma_k1)
    gates = schedule.gates_per_width
    for round_index, gate in enumerate(gates):
        lines = label_points_by_camera(camera, points_px, curves, gate * W)
        if sum(len(p) for p in lines.values()) < 8:
            break
        scale = min(max(schedule.cauchy_per_gate * gate, schedule.cauchy_min_per_width), schedule.cauchy_max_per_width)
        # k1 is held at 0 in the first rounds: with a wrong labelling it trades against f and drifts.
        fixed = () if round_index >= min(schedule.k1_free_from_round, len(gates) - 1) else (1,)
        if len(lines) < config.min_classes_free_position:
            fixed = (1, 5, 6, 7)  # one or two markings (a circle alone): the focal point and k1 are not observable
        elif hold_position:
            fixed = fixed + (5, 6, 7)
        round_config = replace(base, cauchy_scale_px=scale * W)
        if round_index < len(gates) - 1:
            round_config = replace(round_config, min_relative_decrease=schedule.early_round_min_relative_decrease)
        camera = fit_camera_to_lines(camera, lines, curves, round_config, position_prior_w=np.asarray(position_w),
                                     fixed=fixed).camera
    return camera


def _image_distance_px(a: Camera, b: Camera, points_w: np.ndarray) -> float:
    """Median pixel distance between the projections by two cameras of the points either shows (inf if none)."""
    uv_a, front_a = a.project(points_w)
    uv_b, front_b = b.project(points_w)
    shown = front_a & front_b & (a.in_image(uv_a) | b.in_image(uv_b))
    return float(np.median(np.linalg.norm(uv_a[shown] - uv_b[shown], axis=1))) if shown.any() else math.inf


def label_points_by_camera(camera: Camera, points_px: np.ndarray, curves: TemplateCurves, gate_px: float,
                           classes=None) -> dict[str, np.ndarray]:
    """Name unlabelled marking points by their nearest projected ground class within gate_px."""
    names = [n for n in (classes or curves.samples_w) if curves.pitch.is_on_ground(n)]
    if not names:
        return {}
    # Every class projected at once (one call, not one per class).
    samples_w, _, joins_next = curves.stacked(names)
    uv, front = camera.project(samples_w)
    ok = front & camera.in_image(uv)
    shown = np.flatnonzero(ok[:-1] & ok[1:] & joins_next)  # segments with both ends in the image, within a class
    if not len(shown):
        return {}
    sizes = [len(curves.samples_w[name]) for name in names]
    class_of_segment = np.append(np.repeat(np.arange(len(names)), sizes)[shown], -1)  # -1: no segment measured
    best_d, best_segment = _nearest_segments(points_px, uv, shown, gate_px + 1.0)
    named = best_d < gate_px
    best_c = np.where(named, class_of_segment[best_segment], -1)
    return {names[j]: points_px[best_c == j] for j in np.flatnonzero(np.bincount(best_c[named], minlength=1) >= 3)}


def _nearest_segments(points_px: np.ndarray, uv: np.ndarray, segments: np.ndarray, reach_px: float):
    """Each point's distance to the nearest of some polyline segments, measured only where it can be within reach.

    The distance to a segment is :func:`~broadtrack_graph.geometry.template.to_segments`; only the pairs of a point
    and a segment whose bounding box grown by ``reach_px`` holds the point are measured
    (:class:`~broadtrack_graph.geometry.point_windows.PointWindows`), so a point's distance is exact where it is under
    ``reach_px`` less the rounding (far below a pixel), else at least that (inf when no segment is measured).

    Args:
        points_px: (M, 2) pixels; uv: (L, 2) polyline samples, pixels; segments: (S,) int, segment s joins samples
            s and s + 1, in the order of preference on ties (ascending).
        reach_px: how far from a segment's bounding box a point is measured.

    Returns:
        distance: (M,) pixels; nearest: (M,) index into ``segments`` of the first segment at that distance (S where
        none is measured).
    """
    m = len(points_px)
    distance, nearest = np.full(m, np.inf), np.full(m, len(segments))
    if not len(segments) or not m:
        return distance, nearest
    a, b = uv[segments], uv[segments + 1]
    d = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-12)
    segment, point = PointWindows(points_px).pairs_in_boxes(np.minimum(a, b) - reach_px, np.maximum(a, b) + reach_px)
    px, py = points_px[point, 0], points_px[point, 1]
    _, dist2 = to_segments(px, py, a[segment, 0], a[segment, 1], d[segment, 0], d[segment, 1], length2[segment])
    pair_distance = np.sqrt(dist2)
    np.minimum.at(distance, point, pair_distance)
    at_best = pair_distance == distance[point]
    np.minimum.at(nearest, point[at_best], segment[at_best])
    return distance, nearest
