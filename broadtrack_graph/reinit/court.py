"""A camera from one frame's marking map, wherever the camera stands: court-model hypotheses, scored, then fitted.

:func:`reinit_from_court` assumes no camera position. It takes the straight markings of the map
(:func:`~broadtrack_graph.detect.marking_structures.marking_lines`), splits them into the pitch's two
directions by vanishing point, and forms every camera that puts two lines of each direction on two
pitch lines of that direction (:mod:`.court_lines`: one homography each, decomposed with the
principal point at the image centre and gated on plausibility; when none explains the map well, also three lines
of one direction with one across, :mod:`.court_pencil`, and the circles, :mod:`.court_circle`). All hypotheses are
scored at once
on the marking map (:meth:`~broadtrack_graph.reinit.map_score.MapScorer.plane_costs`: the template
found in the map and the map explained by the template), the best ``refit_top`` are solved again on every straight
marking each explains and join as hypotheses of their own (:mod:`.court_refit`: four lines place a narrow view's
vanishing points poorly); the best distinct few are fitted with the
label-and-fit rounds (:func:`~broadtrack_graph.reinit.mask.refine_on_map`, k1 and the focal point
free) and the best fit is returned with its confidence, when the markings it explains fix it with a constraint to
spare (:func:`~broadtrack_graph.geometry.determinable.fixes_camera`: counted on the map, one more constraint than
the camera has unknowns, ``surplus_constraints``): a camera that only lays one line on the one marking in view is
not returned. One that a circle and a line fix exactly is returned only at ``exact_fit_confidence``: laid on them, a
wrong camera explains them as well, so the agreement of an exact fit with its markings is optimistic.

The twin: the markings are unchanged by a half turn about the centre spot, so every hypothesis has
a twin that explains the map as well (the same view from the other end). The rule that decides
here: the focal point on the main camera's side (y > 0) wins; a camera on the halfway line's axis
(|y| under ``twin_tie_m``) is kept at x < 0. A tracker that knows a camera's tripod decides first
(its guesses are tried before this search). ``ReinitResult.twin`` carries the other camera.

Conventions: pitch frame in metres, origin at the centre spot, z down. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from broadtrack_graph.detect.marking_structures import MarkingStructureConfig, outline_in_image
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import determinability, fixes_camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.confidence import camera_confidence
from broadtrack_graph.reinit.court_circle import (
    CourtCircleConfig,
    circle_line_homographies,
    circle_pole_homographies,
    pitch_circle_chords,
)
from broadtrack_graph.reinit.court_depth import most_confident_along_line_of_sight
from broadtrack_graph.reinit.court_families import CourtLineConfig, line_families, normalised_lines
from broadtrack_graph.reinit.court_lines import (
    cameras_from_homographies,
    concatenate,
    line_hypotheses,
    pitch_line_offsets,
    pixel_homographies,
)
from broadtrack_graph.reinit.court_pencil import CourtPencilConfig, pencil_hypotheses
from broadtrack_graph.reinit.court_refit import pitch_lines, refit_on_lines
from broadtrack_graph.reinit.frame import plausible_position
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.map_score import best_distinct
from broadtrack_graph.reinit.mask import fit_points, map_structures, refine_on_map
from broadtrack_graph.reinit.mask_config import MaskSearchConfig
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult


@dataclass(frozen=True)
class CourtConfig:
    """Settings of :func:`reinit_from_court` (pixels at the frame size unless stated)."""

    # the hypotheses of the straight markings (and their gates); 8 second directions to each first: a banner's or a
    # board's two edges meet in a point that outvotes the pitch's own second direction
    lines: CourtLineConfig = CourtLineConfig(second_candidates=8)
    # the circles' hypotheses (a circle with its chord, the centre circle with a touchline)
    circle: CourtCircleConfig = CourtCircleConfig()
    # three lines of one direction and one across (tried with the circles)
    pencil: CourtPencilConfig = CourtPencilConfig()
    # The map's structures, scores and the label-and-fit rounds: more straight markings than the position searches
    # take (a goal net's strands or a board's edges can outnumber the pitch lines in view).
    # The hypothesis's focal point is not a tripod guess: at a tight zoom it can sit 10-20 m off along the line of
    # sight, so the fit holds it loosely.
    # A goal net's strands are dropped from 48 lines before the 24 best supported are kept, and the map's pieces are
    # cut along the long straight markings before ellipses are fitted to them (an arc meets its line).
    search: MaskSearchConfig = MaskSearchConfig(
        structures=MarkingStructureConfig(max_lines=24, candidate_lines=48, ellipse_cut_line_px=160.0),
        position_sigma_m=25.0, max_fit_points=250)
    min_marking_points: int = 10  # fewer marking points: no camera, said at once
    max_hypotheses: int = 20_000  # plausible hypotheses scored at most: the splits of the lines past it are not tried
    refine_top_k: int = 3  # the best distinct hypotheses fitted
    refine_cost_share: float = 0.6  # ... after the first, only those scoring this share of its score
    confidence_margin: float = 0.1  # a fit this much more confident than the best scoring one replaces it (the
    #                                 margin a new camera needs to replace a chain's: TrackingConfig.reinit_switch_margin)
    distinct_per_width: float = 0.02  # hypotheses closer than this in the image count as one
    twin_tie_m: float = 2.0  # |y| under this: the twin is decided by x (x < 0 kept)
    # The markings the best camera explains must give this many constraints more than its 7 unknowns: a camera from
    # nothing that they fix exactly (a circle and one line) lays itself on them whether it is right or not.
    surplus_constraints: int = 1
    # ... or, fixed exactly (no constraint to spare), at this confidence at least: the fit lays the camera on the
    # markings whether it is right or not, so its agreement with them is optimistic (1.01: never)
    exact_fit_confidence: float = 0.8
    # ... after fits from starts along its line of sight at these factors of its distance (reinit.court_depth): an
    # ellipse's error moves an exact fit along it
    exact_fit_depth_factors: tuple[float, ...] = (0.4, 0.48, 0.58, 0.69, 0.83, 1.2, 1.44, 1.73, 2.08, 2.5)
    refit_top: int = 32  # the best hypotheses solved again on every straight marking they explain ...
    refit_min_lines: int = 4  # ... when they explain this many (both directions among them) ...
    refit_gate_per_width: float = 0.02  # ... each with both ends within this share of the width of its pitch line
    rescore_top: int = 64  # hypotheses scored coarsely first (every second sample), these best ones again in full
    prescore_keep: int = 2048  # over this many hypotheses, all are scored on every fourth sample first, these go on
    circles_below_score: float = 0.6  # the centre circle is tried when no straight markings' hypothesis scores this
    centre_circle_min_coverage: float = 0.7  # map pixels per pixel of outline in view of an ellipse taken as the
    #                                          centre circle beside a touchline (painted all round; an arc is not)


def reinit_from_court(marking_mask: np.ndarray, marking_points_px: np.ndarray, frame_size: tuple[int, int],
                      pitch: PitchTemplate | None = None, curves: TemplateCurves | None = None,
                      field_mask: np.ndarray | None = None, config: CourtConfig = CourtConfig()) -> ReinitResult:
    """A camera for a frame from its unlabelled marking map, with no guess of where the camera stands.

    Args:
        marking_mask: bool marking map (frame size or a reduced size of the same aspect ratio).
        marking_points_px: (M, 2) centre-line points of the markings, frame pixels.
        frame_size: (W, H) of the frame (the camera's resolution).
        field_mask: optional bool map of the playing surface (for the confidence).

    Returns:
        ReinitResult: the camera at frame_size with its confidence (``score.jaccard``) and its twin
        (``twin``), ``tried`` hypotheses; or camera None and a one-line reason.
    """
    pitch = pitch or PitchTemplate()
    curves = curves or TemplateCurves(pitch)
    W, H = frame_size
    points_px = np.asarray(marking_points_px, float).reshape(-1, 2)
    if not marking_mask.any() or len(points_px) < config.min_marking_points:
        return ReinitResult(None, None, "", "too few marking pixels")
    structures = map_structures(marking_mask, points_px, (W, H), pitch, config.search)
    lines = structures.lines
    hypotheses, costs = _line_hypotheses(structures, (W, H), pitch, config)
    tiers = _later_tiers(structures, (W, H), pitch, config)
    # Each later tier joins while nothing explains the map well yet (circles_below_score) ...
    while tiers and not (len(costs) and -costs.min() >= config.circles_below_score):
        hypotheses, costs = _joined(hypotheses, costs, tiers.pop(0)(), structures, (W, H), config)
    hypotheses, costs = _joined(hypotheses, costs, _refitted(hypotheses, costs, structures, (W, H), pitch, config),
                                structures, (W, H), config)
    if not len(hypotheses):
        return ReinitResult(None, None, "", f"no plausible camera puts the markings on the pitch ({len(lines)} "
                                            "straight, no circle with them)")

    def confidence_of(camera: Camera) -> float:
        return camera_confidence(camera, marking_mask, curves, field_mask=field_mask)

    def walked(camera: Camera) -> Camera | None:  # an exact fit's depth (court_depth)
        other = most_confident_along_line_of_sight(camera, fit_points(points_px, config.search), curves, config.search,
                                                   config.exact_fit_depth_factors, confidence_of)
        return None if other is None else _main_side(other, config.twin_tie_m)

    result = _judged(_fitted(hypotheses, costs, np.arange(len(costs)), structures, points_px, (W, H), curves,
                             confidence_of, config), marking_mask, field_mask, pitch, curves, config, walked)
    # ... and the tiers left join when the best camera so far is not one to return: their hypotheses alone are
    # fitted then (the rejected ones would be chosen again).
    left = [tier() for tier in tiers] if result.camera is None else []
    if any(len(part) for part in left):
        first = len(costs)
        for part in left:
            hypotheses, costs = _joined(hypotheses, costs, part, structures, (W, H), config)
        later = _judged(_fitted(hypotheses, costs, np.arange(first, len(costs)), structures, points_px, (W, H),
                                curves, confidence_of, config), marking_mask, field_mask, pitch, curves, config,
                        walked)
        result = later if later.camera is not None else result
    return replace(result, tried=len(hypotheses))


def _refitted(hypotheses, costs, structures, frame_size, pitch: PitchTemplate, config: CourtConfig):
    """The ``refit_top`` best hypotheses solved again on every straight marking each explains
    (:func:`~broadtrack_graph.reinit.court_refit.refit_on_lines`), as hypotheses of their own."""
    top = np.argsort(costs)[:config.refit_top]
    top = top[np.isfinite(costs[top])]
    lines = structures.lines
    if not len(top) or len(lines) < config.refit_min_lines:
        return concatenate([])
    _, s, centre = normalised_lines(lines, frame_size)  # the hypotheses' image coordinates: (u - centre) / s
    ends = np.array([[line.centre_px + e * line.direction for e in line.extent_px] for line in lines])
    gate_n = config.refit_gate_per_width * frame_size[0] / s
    H_n, refitted = refit_on_lines(hypotheses.H_n[top], (ends - centre) / s, pitch_lines(*pitch_line_offsets(pitch)),
                                   gate_n, config.refit_min_lines)
    return cameras_from_homographies(H_n[refitted], frame_size, pitch, config.lines)


def _later_tiers(structures, frame_size, pitch: PitchTemplate, config: CourtConfig) -> list:
    """The hypotheses tried after the straight markings', in order, each a call (an empty set when its markings are
    missing): three lines of one direction and one across (a zoomed goal mouth), a circle with the
    line across it, then the centre circle with a touchline (more hypotheses, and looser: tried last)."""
    lines = structures.lines

    def pencil():
        if len(lines) < 4:
            return concatenate([])
        return pencil_hypotheses(lines, frame_size, pitch, config.pencil, config.lines)

    def circles(across: bool):
        if not lines:
            return concatenate([])
        # An arc's piece fitted alone and an ellipse fitted through it and another piece are two estimates of one
        # circle's image, a few per cent apart on a short arc: both are tried.
        ellipses = structures.ellipses() + structures.border_ellipses() + structures.arcs()
        return _circle_hypotheses(ellipses, lines, frame_size, pitch, config, across)

    return [pencil, lambda: circles(True), lambda: circles(False)]


def _joined(hypotheses, costs, part, structures, frame_size, config: CourtConfig):
    """The hypotheses and costs with ``part``'s (scored on the map) after them."""
    if not len(part):
        return hypotheses, costs
    scores = _scores(part, structures.scorer, frame_size, config.search, config.rescore_top, config.prescore_keep)
    return concatenate([hypotheses, part]), np.concatenate([costs, scores])


def _fitted(hypotheses, costs, among: np.ndarray, structures, points_px, frame_size, curves: TemplateCurves,
            confidence_of, config: CourtConfig) -> Camera | None:
    """The best camera fitted from the best distinct few of the hypotheses ``among`` (indices), or None: the best
    scoring on the map, unless another fit is more confident (``confidence_of``) by ``confidence_margin``, then the
    most confident. The map's score ranks fits a few pixels apart well, wrong fits poorly: a wrong camera laid over
    the map's clutter (the boards, the stands' rows) can score above the right one, which the confidence, reading
    the template's own markings in the map, rates far below it."""
    W, H = frame_size
    search = config.search
    H_px = pixel_homographies(hypotheses, (W, H))
    # A hypothesis and its twin score the same: the twin rule orders them before the distinct choice.
    C = hypotheses.C_w[among]
    twin_side = np.where(np.abs(C[:, 1]) >= config.twin_tie_m, C[:, 1] < 0, C[:, 0] > 0)
    focal_px = hypotheses.focal_n[among] * (W / 2.0)
    pans, tilts = hypotheses.angles_rad[among, 0], hypotheses.angles_rad[among, 1]
    # The image of a hypothesis and of its twin are the same: distinct by image, the kept side first.
    order_costs = costs[among] + 1e-6 * twin_side
    chosen = [int(among[k]) for k in best_distinct(np.where(twin_side, pans + math.pi, pans), tilts, focal_px,
                                                    order_costs, config.refine_top_k, config.distinct_per_width * W, W)]
    if not chosen:
        return None
    points = fit_points(points_px, search)
    fits = []  # (fit score, confidence, camera)
    for k in chosen:
        if costs[k] > config.refine_cost_share * costs[chosen[0]]:
            break
        start = camera_through(H_px[k], hypotheses.sign[k], _camera_of(hypotheses, k, W, H), curves)
        camera = refine_on_map(start, points, start.position_m, curves, search, search.schedule)
        score = -structures.fine_scorer.camera_cost(camera, search.fit_hit_px, search.fit_point_px)
        fits.append((score, confidence_of(camera), camera))
        if score >= search.accept_fit_score:
            break  # a fit this good is not beaten by a worse-scoring hypothesis
    best, confident = max(fits, key=lambda fit: fit[0]), max(fits, key=lambda fit: fit[1])
    return _main_side((confident if confident[1] >= best[1] + config.confidence_margin else best)[2], config.twin_tie_m)


def _judged(camera: Camera | None, marking_mask, field_mask, pitch: PitchTemplate, curves: TemplateCurves,
            config: CourtConfig, walked=None) -> ReinitResult:
    """The fitted camera returned with its confidence and twin, or None and why (module docstring). An exact fit
    under ``exact_fit_confidence`` is replaced by the most confident fit along its line of sight (``walked``: a camera
    or None), judged the same way."""
    if camera is None:
        return ReinitResult(None, None, "", "no hypothesis shows the template in the image")
    if not plausible_position(camera.position_m, pitch):
        return ReinitResult(None, None, "", "the best camera's focal point is not a broadcast camera's (on the pitch "
                                            "or under the grass)")
    fixed = determinability(camera, pitch, explained_by=marking_mask)
    why = f"the markings the best camera explains do not fix it ({fixed.x_lines} and {fixed.y_lines} lines, " \
          f"{len(fixed.curves)} circles"
    to_spare = fixes_camera(fixed, config.surplus_constraints)
    if not to_spare and not fixes_camera(fixed):
        return ReinitResult(None, None, "", why + ")")
    confidence = camera_confidence(camera, marking_mask, curves, field_mask=field_mask)
    if not to_spare and confidence < config.exact_fit_confidence:
        other = walked(camera) if walked is not None else None
        if other is not None:
            return _judged(other, marking_mask, field_mask, pitch, curves, config)
        return ReinitResult(None, None, "", why + f", exactly, at {confidence:.2f})")
    position = tuple(round(float(v)) for v in camera.position_m)
    return replace(ReinitResult(camera, LabelledScore(confidence, 0, 0, 0, 0.0, 0.0), f"court model at {position}"),
                   twin=twin_camera(camera))


def _line_hypotheses(structures, frame_size, pitch: PitchTemplate, config: CourtConfig):
    """The straight markings' hypotheses (the likeliest splits of the lines first, until ``max_hypotheses``: a
    frame full of lines stays bounded) and their map costs."""
    lines = structures.lines
    support = np.array([line.support_px for line in lines])
    parts = []
    for families in line_families(lines, frame_size, config.lines):
        parts.append(line_hypotheses(families, support, pitch, frame_size, config.lines))
        if sum(len(part) for part in parts) >= config.max_hypotheses:
            break
    hypotheses = concatenate(parts)
    return hypotheses, _scores(hypotheses, structures.scorer, frame_size, config.search, config.rescore_top,
                               config.prescore_keep)


def _circle_hypotheses(ellipses, lines, frame_size, pitch: PitchTemplate, config: CourtConfig, across: bool):
    """The circles' hypotheses: each ellipse of the map as each pitch circle with each straight marking as the line
    across it (the halfway line, a 16.5 m line; ``across``), or as the centre circle with each marking that misses it
    as a touchline."""
    if not ellipses:
        return concatenate([])
    lines_n, _, _ = normalised_lines(lines, frame_size)
    d = pitch.dimensions
    if across:
        found = circle_line_homographies(ellipses, lines_n, frame_size, pitch_circle_chords(pitch), config.circle)
    else:
        # Only an ellipse drawn along most of its outline in view can be the centre circle here: a penalty arc
        # (under a third of its circle) with a touchline would explain the view as well, 41.5 m along the pitch.
        whole = [e for e in ellipses if e.support_px >= config.centre_circle_min_coverage * outline_in_image(
            e.centre_px[0], e.centre_px[1], *e.semi_axes_px, e.angle_rad, *frame_size)[1]]
        found = circle_pole_homographies(whole, lines_n, frame_size, d.centre_circle_radius_m, d.width_m / 2,
                                         config.circle)
    return cameras_from_homographies(found, frame_size, pitch, config.lines)


def _scores(hypotheses, scorer, frame_size, search: MaskSearchConfig, rescore_top: int, prescore_keep: int
            ) -> np.ndarray:
    """(K,) map costs of the hypotheses: all on every second template sample and marking point (when there are more
    than ``prescore_keep``, only the ``prescore_keep`` best on every fourth), the ``rescore_top`` best again in full
    (the others inf: they are not fitted)."""
    if not len(hypotheses):
        return np.zeros(0)
    H_px = pixel_homographies(hypotheses, frame_size)
    px_per_m = hypotheses.focal_n * (frame_size[0] / 2.0) * hypotheses.scale_m
    sign = hypotheses.sign
    kept = np.arange(len(H_px))
    if len(kept) > prescore_keep:
        rough = scorer.plane_costs(H_px, sign, px_per_m, search.coarse_hit_px, search.coarse_point_px,
                                   thin=2 * search.coarse_thin)
        kept = np.sort(np.argsort(rough)[:prescore_keep])
    costs = np.full(len(H_px), np.inf)
    costs[kept] = scorer.plane_costs(H_px[kept], sign[kept], px_per_m[kept], search.coarse_hit_px,
                                     search.coarse_point_px, thin=search.coarse_thin)
    top = np.argsort(costs)[:rescore_top]
    top = top[np.isfinite(costs[top])]
    fine = scorer.plane_costs(H_px[top], sign[top], px_per_m[top], search.score_hit_px, search.score_point_px)
    out = np.full(len(costs), np.inf)
    out[top] = fine
    return out


def _camera_of(hypotheses, k: int, W: int, H: int) -> Camera:
    pan, tilt, roll = (float(v) for v in hypotheses.angles_rad[k])
    return Camera(float(hypotheses.focal_n[k] * W / 2.0), 0.0, pan, tilt, roll, hypotheses.C_w[k], W, H)


def camera_through(H_px: np.ndarray, sign: float, start: Camera, curves: TemplateCurves, per_class: int = 12) -> Camera:
    """The camera (k1 held at 0) that draws the ground template where the homography H_px (pitch (x, y, 1) metres ->
    pixels; a ground point X is in front when ``sign * (H_px X)_z > 0``) draws it, fitted from ``start`` (its
    decomposition).

    At a tight zoom the homography is nearly affine: the focal length and the distance along the line of sight
    that its decomposition gives can be far off (10-20 m, the template hundreds of pixels off) while H itself is
    right. Fitted to H's own image of every marking it shows, with each point's marking known, the camera lands
    on it from there.
    """
    W = start.width_px
    lines = {}
    for name, samples_w in curves.samples_w.items():
        if not curves.pitch.is_on_ground(name):
            continue
        uvw = np.column_stack([samples_w[:, :2], np.ones(len(samples_w))]) @ H_px.T
        ahead = sign * uvw[:, 2] > 1e-9
        uv = uvw[:, :2] / np.where(ahead, uvw[:, 2], 1.0)[:, None]
        shown = ahead & start.in_image(uv) & np.all(np.isfinite(uv), axis=1)
        if shown.sum() >= 3:
            lines[name] = uv[shown][np.linspace(0, shown.sum() - 1, min(per_class, int(shown.sum()))).astype(int)]
    if sum(len(p) for p in lines.values()) < 8:
        return start
    config = LineFitConfig(cauchy_scale_px=0.05 * W, polish_power=0.0, iterations=20, sigma_k1=1e-3)
    return fit_camera_to_lines(start, lines, curves, config, fixed=(1,)).camera


def twin_camera(camera: Camera) -> Camera:
    """The camera turned half round the centre spot: it sees the markings exactly as ``camera`` does."""
    x, y, z = camera.position_m
    pan = math.remainder(camera.pan_rad + math.pi, 2 * math.pi)
    return camera.replace(pan_rad=pan, position_m=np.array([-x, -y, z]))


def _main_side(camera: Camera, tie_m: float) -> Camera:
    """``camera`` or its twin, by the twin rule of the module docstring."""
    x, y, _ = camera.position_m
    other_side = y < 0 if abs(y) >= tie_m else x > 0
    return twin_camera(camera) if other_side else camera


def court_reinit(detections, frame_size: tuple[int, int], curves: TemplateCurves) -> ReinitResult:
    """:func:`reinit_from_court` on a frame's detections (its marking map, marking points and field mask)."""
    return reinit_from_court(detections.marking_mask, detections.marking_points_px, frame_size, curves.pitch, curves,
                             detections.field_mask)
