"""The court model's last steps: the best distinct hypotheses fitted on the marking map, one fit kept, then judged.

:func:`fitted_hypotheses` fits the best distinct few hypotheses (the label-and-fit rounds of
:func:`~broadtrack_graph.reinit.mask.refine_on_map`, k1 and the focal point free, each started from the camera that
draws its homography's template, :func:`camera_through`; a fit whose focal point slid onto the playing area fitted
again from its starts moved back along their lines of sight, :func:`off_the_pitch`, the focal point held there; one
that slid out of the stadium is not a broadcast camera's, and is not kept when another fit is);
:func:`kept_camera` keeps the best scoring fit on the map
(of those standing where a broadcast camera can, when any does), or the most confident one when it is more confident
by ``confidence_margin``. :func:`judged` returns it with its confidence when it stands where a broadcast camera can,
and the markings it explains fix it with a constraint to spare
(:func:`~broadtrack_graph.geometry.determinable.fixes_camera`); fixed exactly (a circle and a line), only at
``exact_fit_confidence``, else after a refit along its line of sight (:mod:`.court_depth`) that reaches it.

The twin: the markings are unchanged by a half turn about the centre spot, so every hypothesis has a twin that
explains the map as well (the same view from the other end, :func:`twin_camera`). The rule that decides here
(:func:`main_side`): the focal point on the main camera's side (y > 0) wins; a camera on the halfway line's axis
(|y| under ``twin_tie_m``) is kept at x < 0. A tracker that knows a camera's tripod decides first (its guesses are
tried before this search). ``ReinitResult.twin`` carries the other camera.

Settings are :class:`~broadtrack_graph.reinit.court_config.CourtConfig`'s. Pitch frame in metres, z down. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import determinability, fixes_camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.court_depth import along_line_of_sight
from broadtrack_graph.reinit.court_lines import pixel_homographies
from broadtrack_graph.reinit.frame import plausible_position
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.map_score import best_distinct
from broadtrack_graph.reinit.mask import fit_points, refine_on_map
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult


@dataclass(frozen=True)
class Fit:
    """One fitted hypothesis: its index, its score on the map (-cost: higher is better), its confidence and the
    camera."""

    index: int
    score: float
    confidence: float
    camera: Camera


def fitted_hypotheses(hypotheses, costs, among: np.ndarray, structures, points_px, frame_size,
                      curves: TemplateCurves, confidence_of, config: CourtConfig, cache: dict | None = None) -> list[Fit]:
    """The best distinct few of the hypotheses ``among`` (indices) fitted on the map, best map cost first. After the
    first, only those scoring ``refine_cost_share`` of its map score; after a fit scoring ``accept_fit_score``, only
    those the map scores alike (within ``fit_tie_cost``): a good fit is not beaten by a hypothesis the map scores
    worse, but the members of a circle-and-line family, whose images of both are the same, score alike and fit
    apart. ``cache``: (camera, score) of the hypotheses fitted before (by homography and sign), filled in."""
    W, H = frame_size
    search = config.search
    cache = {} if cache is None else cache
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
    points = fit_points(points_px, search)
    fits: list[Fit] = []
    good_cost = None  # the map cost of the first hypothesis whose fit scores accept_fit_score
    for k in chosen:
        if costs[k] > config.refine_cost_share * costs[chosen[0]]:
            break
        if good_cost is not None and costs[k] > good_cost + config.fit_tie_cost:
            break
        key = (hypotheses.H_n[k].tobytes(), float(hypotheses.sign[k]))
        if key not in cache:
            decomposed = hypothesis_camera(hypotheses, k, W, H)
            start = camera_through(H_px[k], hypotheses.sign[k], decomposed, curves)
            camera = refine_on_map(start, points, start.position_m, curves, search, search.schedule)
            if not plausible_position(camera.position_m, curves.pitch, max_distance_m=math.inf):  # over the pitch
                camera = _held_off_the_pitch(camera, (start, decomposed), points, curves, structures, search)
            cache[key] = camera, -structures.fine_scorer.camera_cost(camera, search.fit_hit_px, search.fit_point_px)
        camera, score = cache[key]
        fits.append(Fit(k, score, confidence_of(camera), camera))
        if score >= search.accept_fit_score and good_cost is None:
            good_cost = costs[k]
    return fits


def _held_off_the_pitch(camera: Camera, starts, points, curves: TemplateCurves, structures, search) -> Camera:
    """A fit whose focal point slid to where no broadcast camera stands (a narrow view draws about the same image from
    anywhere along its line of sight) fitted again from each of its ``starts`` moved back along its line of sight to
    the nearest place one can (:func:`off_the_pitch`), the focal point held there; the best on the map of those, or
    ``camera`` when no start can be moved."""
    moved = [m for m in {id(s): off_the_pitch(s, curves.pitch) for s in starts}.values() if m is not None]
    held = [refine_on_map(m, points, m.position_m, curves, search, search.schedule, hold_position=True) for m in moved]
    return min(held, key=lambda c: structures.fine_scorer.camera_cost(c, search.fit_hit_px, search.fit_point_px),
               default=camera)


def kept_camera(fits: list[Fit], pitch: PitchTemplate, config: CourtConfig) -> Camera | None:
    """The camera of one of the fits, or None for none: the best scoring on the map, unless another fit is more
    confident by ``confidence_margin``, then the most confident; of those standing where a broadcast camera can when
    any does. The map's score ranks fits a few pixels apart well, wrong fits poorly: a wrong camera laid over the
    map's clutter (the boards, the stands' rows) can score above the right one, which the confidence, reading the
    template's own markings in the map, rates far below it. A circle and a line fix a camera exactly, and fits from
    nearby starts can lay the same image from different depths along the line of sight."""
    kept = kept_fit(fits, pitch, config)
    return None if kept is None else main_side(kept.camera, config.twin_tie_m)


def kept_fit(fits: list[Fit], pitch: PitchTemplate, config: CourtConfig) -> Fit | None:
    """The fit whose camera :func:`kept_camera` keeps (before the twin rule), or None."""
    if not fits:
        return None
    fits = [fit for fit in fits if plausible_position(fit.camera.position_m, pitch)] or fits
    best, confident = max(fits, key=lambda fit: fit.score), max(fits, key=lambda fit: fit.confidence)
    return confident if confident.confidence >= best.confidence + config.confidence_margin else best


def judged(camera: Camera | None, marking_mask, pitch: PitchTemplate, config: CourtConfig, confidence_of,
            walked=None) -> ReinitResult:
    """The fitted camera returned with its confidence (``confidence_of``) and twin, or None and why (module
    docstring). An exact fit under ``exact_fit_confidence`` is replaced by the most confident fit along its line of
    sight (``walked``: a camera or None), judged the same way."""
    if camera is None:
        return ReinitResult(None, None, "", "no hypothesis shows the template in the image")
    if not plausible_position(camera.position_m, pitch):
        return ReinitResult(None, None, "", "the best camera's focal point is not a broadcast camera's (on the pitch, "
                                            "under the grass or out of the stadium)")
    fixed = determinability(camera, pitch, explained_by=marking_mask)
    why = f"the markings the best camera explains do not fix it ({fixed.x_lines} and {fixed.y_lines} lines, " \
          f"{len(fixed.curves)} circles"
    to_spare = fixes_camera(fixed, config.surplus_constraints)
    if not to_spare and not fixes_camera(fixed):
        return ReinitResult(None, None, "", why + ")")
    confidence = confidence_of(camera)
    if not to_spare and confidence < config.exact_fit_confidence:
        other = walked(camera) if walked is not None else None
        if other is not None:
            return judged(other, marking_mask, pitch, config, confidence_of)
        return ReinitResult(None, None, "", why + f", exactly, at {confidence:.2f})")
    position = tuple(round(float(v)) for v in camera.position_m)
    return replace(ReinitResult(camera, LabelledScore(confidence, 0, 0, 0, 0.0, 0.0), f"court model at {position}"),
                   twin=twin_camera(camera), explained=fixed)


def hypothesis_camera(hypotheses, k: int, W: int, H: int) -> Camera:
    """Hypothesis ``k``'s camera decomposed from its homography (k1 0), at (W, H)."""
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
    # every ground class at once: H's image of its samples, then read class by class
    names = [name for name in curves.samples_w if curves.pitch.is_on_ground(name)]
    samples_w = curves.stacked(names)[0]
    uvw = np.column_stack([samples_w[:, :2], np.ones(len(samples_w))]) @ H_px.T
    ahead = sign * uvw[:, 2] > 1e-9
    uv = uvw[:, :2] / np.where(ahead, uvw[:, 2], 1.0)[:, None]
    shown = ahead & start.in_image(uv) & np.all(np.isfinite(uv), axis=1)
    sizes = [len(curves.samples_w[name]) for name in names]
    starts = np.cumsum(sizes) - sizes
    counts = np.add.reduceat(shown, starts) if len(names) else np.zeros(0, int)
    lines = {}
    for j in np.flatnonzero(counts >= 3):
        count = int(counts[j])
        on_image = uv[starts[j]:starts[j] + sizes[j]][shown[starts[j]:starts[j] + sizes[j]]]
        lines[names[j]] = on_image[np.linspace(0, count - 1, min(per_class, count)).astype(int)]
    if sum(len(p) for p in lines.values()) < 8:
        return start
    config = LineFitConfig(cauchy_scale_px=0.05 * W, polish_power=0.0, iterations=20, sigma_k1=1e-3)
    return fit_camera_to_lines(start, lines, curves, config, fixed=(1,)).camera


def off_the_pitch(camera: Camera, pitch: PitchTemplate, margin_m: float = 0.5) -> Camera | None:
    """``camera`` itself where a broadcast camera can stand (:func:`~broadtrack_graph.reinit.frame.plausible_position`),
    else moved back along its line of sight to the nearest such place (``margin_m`` past the pitch's edge), its focal
    length scaled with its distance to the ground point it looks at (:func:`~.court_depth.along_line_of_sight`: that
    point's surroundings drawn about the same size); None when its optical axis misses the ground ahead."""
    if plausible_position(camera.position_m, pitch):
        return camera
    axis, position = camera.optical_axis_w, np.asarray(camera.position_m, float)
    if axis[2] <= 1e-6 or position[2] >= 0:
        return None
    look_at = position + (-position[2] / axis[2]) * axis
    away = position - look_at
    half = np.array([pitch.dimensions.length_m / 2, pitch.dimensions.width_m / 2]) + margin_m
    factors = [(sign * half[i] - look_at[i]) / away[i] for i in (0, 1) for sign in (-1.0, 1.0) if abs(away[i]) > 1e-9]
    factors = [k for k in factors if k > 1.0]
    if not factors:
        return None
    moved = along_line_of_sight(camera, [min(factors)])[0]
    return moved if plausible_position(moved.position_m, pitch) else None


def twin_camera(camera: Camera) -> Camera:
    """The camera turned half round the centre spot: it sees the markings exactly as ``camera`` does."""
    x, y, z = camera.position_m
    pan = math.remainder(camera.pan_rad + math.pi, 2 * math.pi)
    return camera.replace(pan_rad=pan, position_m=np.array([-x, -y, z]))


def main_side(camera: Camera, tie_m: float) -> Camera:
    """``camera`` or its twin, by the twin rule of the module docstring."""
    x, y, _ = camera.position_m
    other_side = y < 0 if abs(y) >= tie_m else x > 0
    return twin_camera(camera) if other_side else camera
