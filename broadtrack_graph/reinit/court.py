"""A camera from one frame's marking map, wherever the camera stands: court-model hypotheses, scored, then fitted.

:func:`reinit_from_court` assumes no camera position. It takes the straight markings of the map
(:func:`~broadtrack_graph.detect.marking_structures.marking_lines`), splits them into the pitch's two directions by
vanishing point, and forms every camera that puts two lines of each direction on two pitch lines of that direction
(:mod:`.court_lines`: one homography each, decomposed with the principal point at the image centre and gated on
plausibility; of the likeliest split first, of every split, formed at once, when none of its cameras explains the map
well or they leave the frame unsettled; when none explains it well, the later tiers of :mod:`.court_tiers`: three lines
of one direction with one across, :mod:`.court_pencil`, and the circles, :mod:`.court_circle`, last on the ellipses and
arcs fitted again on the markings' centre points, :mod:`~broadtrack_graph.detect.ellipse_refit`; as tiers of last
resort, once the first fits are in, two lines of one direction with one across, the camera level, :mod:`.court_level`
(taken only at ``exact_fit_confidence``: the roll assumed, three lines fix it exactly), then a circle's arc and its
chord rectified under the camera model, :mod:`.court_arcs`, or with one line of each direction beside it,
:mod:`.court_arc_corners`, fitted apart, taken only with a constraint to spare, and joined only when the tiers before
them leave the frame without a camera ``look_further_below`` confident). All hypotheses are scored at once on the
marking map (:meth:`~broadtrack_graph.reinit.map_score.MapScorer.plane_costs`: the template found in the map and the map
explained by the template; coarsely first, the precision read only of those whose recall could rank them among the
best), the best ``refit_top`` are solved again on every straight marking each explains and join as hypotheses of their
own (:mod:`.court_refit`: four lines place a narrow view's vanishing points poorly); the best distinct few are fitted
with the label-and-fit rounds (with no camera kept of them, or no fit explaining the map well, the tiers left are fitted
too; for a camera under ``look_further_below`` confident the tiers left, their fit replacing it when more confident by
``confidence_margin``) and one fit is kept and judged (:mod:`.court_fit`): it is returned with its confidence when the
markings it explains fix it with a constraint to spare, counted on the map, and a camera fixed exactly (a circle and a
line) only at ``exact_fit_confidence``: laid on them, a wrong camera explains them as well. A narrow view's camera
returned under ``narrow_view_walk_below`` confident is fitted again from starts along its line of sight and the most
confident fit kept (:mod:`.court_depth`: its distance and focal length trade off). A camera returned ``polish_from``
confident is fitted once more on up to ``polish_points`` of the markings' points (the fits take fewer, for their speed)
and judged again. Every hypothesis has a twin turned half round the centre spot that explains the map as well; the main
camera's side (y > 0) is kept (:func:`~broadtrack_graph.reinit.court_fit.main_side`) and ``ReinitResult.twin`` carries
the other.

Conventions: pitch frame in metres, origin at the centre spot, z down. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from broadtrack_graph.detect.motion_blur import MotionBlur
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.confidence import camera_confidence
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.court_depth import most_confident_along_line_of_sight
from broadtrack_graph.reinit.court_families import hidden_lengths_px, line_families, normalised_lines
from broadtrack_graph.reinit.court_fit import fitted_hypotheses, judged, kept_fit, main_side
from broadtrack_graph.reinit.court_lines import (
    concatenate,
    pitch_line_offsets,
    pixel_homographies,
    plausible_cameras,
    split_hypotheses,
)
from broadtrack_graph.reinit.court_refit import pitch_lines, refit_on_lines
from broadtrack_graph.reinit.court_tiers import Tier, later_tiers
from broadtrack_graph.reinit.mask import fit_points, map_structures, refine_on_map
from broadtrack_graph.reinit.mask_config import MaskSearchConfig
from broadtrack_graph.reinit.scoring import ReinitResult


def reinit_from_court(marking_mask: np.ndarray, marking_points_px: np.ndarray, frame_size: tuple[int, int],
                      pitch: PitchTemplate | None = None, curves: TemplateCurves | None = None,
                      field_mask: np.ndarray | None = None, config: CourtConfig = CourtConfig(),
                      player_mask: np.ndarray | None = None, motion_blur: MotionBlur | None = None) -> ReinitResult:
    """A camera for a frame from its unlabelled marking map, with no guess of where the camera stands.

    Args:
        marking_mask: bool marking map (frame size or a reduced size of the same aspect ratio).
        marking_points_px: (M, 2) centre-line points of the markings, frame pixels.
        frame_size: (W, H) of the frame (the camera's resolution).
        field_mask: optional bool map of the playing surface (for the confidence).
        player_mask: optional bool map of the players (any size of the frame's aspect ratio): a line's stretch
            they hide is not asked to be drawn (:func:`~.court_families.hidden_lengths_px`).
        motion_blur: the frame's motion blur (length in frame pixels), or None: the confidence does not expect the
            markings it smears out (:mod:`~broadtrack_graph.reinit.confidence`).

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
    hidden = hidden_lengths_px(lines, player_mask, W)
    hypotheses, costs, every_split = _line_hypotheses(structures, (W, H), pitch, config, hidden)
    tiers: list[Tier] = []
    tier_at: list = [None] * len(costs)  # each hypothesis's later tier (None: the straight markings')
    fit_cache: dict = {}  # a hypothesis fitted in the likeliest split's pass is not fitted again in every split's

    def joined_tier(hypotheses, costs):
        tier = tiers.pop(0)
        start = len(costs)
        hypotheses, costs = _joined(hypotheses, costs, tier.hypotheses(), structures, (W, H), config)
        tier_at.extend([tier] * (len(costs) - start))
        return hypotheses, costs

    known: list[tuple[Camera, float]] = []  # the fits' confidences, asked again when a fit is judged

    def confidence_of(camera: Camera) -> float:
        for seen, confidence in known:
            if seen is camera:
                return confidence
        known.append((camera, camera_confidence(camera, marking_mask, curves, field_mask=field_mask,
                                                motion_blur=motion_blur)))
        return known[-1][1]

    walks: dict = {}  # a camera judged again (one fit kept of several pools) is not walked again

    def walked(camera: Camera, factors=config.exact_fit_depth_factors) -> Camera | None:  # its depth (court_depth)
        key = (camera.to_vector().tobytes(), camera.extra_distortion, camera.principal_point_px, tuple(factors))
        if key not in walks:
            other = most_confident_along_line_of_sight(camera, fit_points(points_px, config.search), curves,
                                                       config.search, factors, confidence_of)
            walks[key] = None if other is None else main_side(other, config.twin_tie_m)
        return walks[key]

    def fitted(among: np.ndarray) -> list:
        return fitted_hypotheses(hypotheses, costs, among, structures, points_px, (W, H), curves, confidence_of, config,
                                 fit_cache)

    # A circle's arc and one line fix a camera exactly but poorly (its depth, and a penalty arc read for the centre
    # circle's), as do two lines and one with the roll assumed: a camera from a tier of last resort, and every camera
    # moved from it, is taken only with a constraint to spare.
    spare_only = replace(config, exact_fit_confidence=math.inf)
    spare_only_results: list[ReinitResult] = []

    def from_last_resort(index: int) -> bool:  # a hypothesis of a tier of last resort (the level cameras', the arcs')
        return tier_at[index] is not None and tier_at[index].last_resort

    def kept_and_judged(fits: list) -> ReinitResult:
        kept = kept_fit(fits, pitch, config)
        camera = None if kept is None else main_side(kept.camera, config.twin_tie_m)
        tier = None if kept is None else tier_at[kept.index]
        if tier is not None and tier.last_resort:
            result = judged(camera, marking_mask, pitch, spare_only, confidence_of)
        else:
            # (an exact fit is walked along its line of sight only in the last pass: the likeliest split's pass ends
            # without a camera there, and every split's is searched)
            result = judged(camera, marking_mask, pitch, config, confidence_of, walked if every_split is None else None)
        if tier is not None and result.camera is not None and result.score.jaccard < tier.min_confidence:
            result = ReinitResult(None, None, "", f"the best camera is under its hypotheses' bar "
                                                  f"({result.score.jaccard:.2f} < {tier.min_confidence:.2f})")
        if tier is not None and tier.last_resort:
            others = [fit for fit in fits if not from_last_resort(fit.index)]
            if result.camera is None and others:  # a fit of the last resort does not take the others' place
                return kept_and_judged(others)
            spare_only_results.append(result)
        return result

    def judged_as(result: ReinitResult) -> CourtConfig:  # the settings a camera moved from result is judged with
        return spare_only if any(result is r for r in spare_only_results) else config

    while True:  # the likeliest split's pass, and every split's when that one leaves the frame unsettled
        tiers[:], tier_at[:] = later_tiers(structures, (W, H), pitch, config, hidden), [None] * len(costs)
        # Each later tier joins while nothing explains the map well yet (explained_well_score), but the tiers of last
        # resort (the level cameras', the arcs': joined only once the first fits are in) ...
        while tiers and not tiers[0].last_resort and not _explains_well(costs, config):
            hypotheses, costs = joined_tier(hypotheses, costs)
        refits, sources = _refitted(hypotheses, costs, structures, (W, H), pitch, config)
        hypotheses, costs = _joined(hypotheses, costs, refits, structures, (W, H), config)
        tier_at.extend(tier_at[k] for k in sources)  # a hypothesis solved again keeps its tier's bar
        while tiers and not len(hypotheses):  # nothing else: the tier of last resort too
            hypotheses, costs = joined_tier(hypotheses, costs)
        if not len(hypotheses):
            return ReinitResult(None, None, "", f"no plausible camera puts the markings on the pitch ({len(lines)} "
                                                "straight, no circle with them)")
        fits = fitted(np.arange(len(costs)))
        result = kept_and_judged(fits)
        poor = result.camera is None or max((fit.score for fit in fits), default=0.0) < config.search.accept_fit_score
        unsettled = poor or result.score.jaccard < config.look_further_below
        if every_split is None or not unsettled:
            break
        # The likeliest split's cameras explain the map well but do not settle the frame: every split's hypotheses,
        # scored together, and the search from them as if they had been formed at once (its fits not made again).
        (hypotheses, costs), every_split = every_split(), None
    if unsettled:
        # No camera, or none of the fits explains the map well: the tiers left join and their best are fitted. One
        # reading of the markings can score a little better on the map than the right reading of another (an arc's
        # ellipse taken as the centre circle beside a touchline, against the same arc with its 16.5 m line across it)
        # and take every fit. One fit is kept of them all, else of the new ones alone (the rejected ones would be
        # chosen again). The sources none of whose hypotheses was fitted are not fitted here: their best added wrong
        # cameras more than right ones (docs/BENCHMARKS.md, Why the defaults). A camera kept that is not confident
        # enough to settle the frame has the tiers left fitted too (a narrow view's penalty arc and 16.5 m line
        # fitted at a third of its distance, the centre circle beside a touchline not joined while that arc's
        # hypothesis explained the map well), and only a fit more confident by confidence_margin replaces it: the
        # map's score ranks fits a few pixels apart well, wrong fits poorly (kept_camera).
        def replacing(more: list) -> ReinitResult:  # the camera the fits of the tiers left give, else result
            if poor:
                for candidates in ([fits + more, more] if fits else [more]) if more else []:  # each judged once
                    later = kept_and_judged(candidates)
                    if later.camera is not None:
                        return later
                return result
            # a camera kept but not settled: only a fit more confident by confidence_margin replaces it (the most
            # confident of the others when an arc's is not taken)
            for pool in (more, [fit for fit in more if not from_last_resort(fit.index)]):
                confident = max(pool, key=lambda fit: fit.confidence, default=None)
                if confident is None or confident.confidence < result.score.jaccard + config.confidence_margin:
                    break
                later = kept_and_judged([confident])
                if later.camera is not None or not from_last_resort(confident.index):
                    return later if later.camera is not None else result
            return result

        def fitted_tiers(last_resort: bool) -> list:  # the tiers left joined (those of last resort, or all others)
            nonlocal hypotheses, costs
            first = len(costs)
            while tiers and tiers[0].last_resort == last_resort:  # the tiers of last resort are the last ones
                hypotheses, costs = joined_tier(hypotheses, costs)
            return fitted(np.arange(first, len(costs))) if len(costs) > first else []

        # The tiers of last resort (the arcs' the slowest) join only when the others leave the frame unsettled.
        more = fitted_tiers(last_resort=False)
        later = replacing(more)
        if tiers and (later.camera is None or later.score.jaccard < config.look_further_below):
            more += fitted_tiers(last_resort=True)  # fitted apart: they take no other's slot
            later = replacing(more)
        result = later
    if (result.camera is not None and result.score.jaccard < config.narrow_view_walk_below
            and result.camera.focal_px >= config.narrow_view_focal_per_width * W):
        # A narrow view's depth along its line of sight: the most confident of the fits from starts along it, judged
        # as every camera is.
        other = walked(result.camera, config.narrow_view_depth_factors)
        if other is not None:
            deeper = judged(other, marking_mask, pitch, judged_as(result), confidence_of)
            result = deeper if deeper.camera is not None else result
    if result.camera is not None and result.score.jaccard >= config.polish_from:
        # The camera returned, fitted on more of the markings' points than the hypotheses' fits take; only one confident
        # enough to be taken at any bar, and kept when it still is (the polish moves no camera over a bar).
        camera, more = result.camera, replace(config.search, max_fit_points=config.polish_points)
        polished = refine_on_map(camera, fit_points(points_px, more), camera.position_m, curves, config.search,
                                 config.polish_schedule)
        again = judged(main_side(polished, config.twin_tie_m), marking_mask, pitch, judged_as(result), confidence_of)
        result = again if again.camera is not None and again.score.jaccard >= config.polish_from else result
    return replace(result, tried=len(hypotheses))


def _refitted(hypotheses, costs, structures, frame_size, pitch: PitchTemplate, config: CourtConfig):
    """The ``refit_top`` best hypotheses solved again on every straight marking each explains
    (:func:`~broadtrack_graph.reinit.court_refit.refit_on_lines`), as hypotheses of their own, with the index of
    each one's source."""
    top = np.argsort(costs)[:config.refit_top]
    top = top[np.isfinite(costs[top])]
    lines = structures.lines
    if not len(top) or len(lines) < config.refit_min_lines:
        return concatenate([]), np.zeros(0, int)
    _, s, centre = normalised_lines(lines, frame_size)  # the hypotheses' image coordinates: (u - centre) / s
    ends = np.array([line.ends_px() for line in lines])
    gate_n = config.refit_gate_per_width * frame_size[0] / s
    H_n, refitted = refit_on_lines(hypotheses.H_n[top], (ends - centre) / s, pitch_lines(*pitch_line_offsets(pitch)),
                                   gate_n, config.refit_min_lines)
    refits, kept = plausible_cameras(H_n[refitted], frame_size, pitch, config.lines)
    return refits, top[refitted][kept]


def _joined(hypotheses, costs, part, structures, frame_size, config: CourtConfig):
    """The hypotheses and costs with ``part``'s (scored on the map) after them."""
    if not len(part):
        return hypotheses, costs
    scores = _scores(part, structures.scorer, frame_size, config.search, config.rescore_top, config.prescore_keep,
                     config.prescore_thin)
    return concatenate([hypotheses, part]), np.concatenate([costs, scores])


def _line_hypotheses(structures, frame_size, pitch: PitchTemplate, config: CourtConfig,
                     hidden_px: np.ndarray | None = None):
    """The straight markings' hypotheses, their map costs and the call giving every split's (or None): of the likeliest
    split of the lines when one of its cameras explains the map well (``explained_well_score``), else of every split
    (likeliest first, until ``max_hypotheses``: a frame full of lines stays bounded), scored together (the coarse
    passes rank the hypotheses of a set against one another)."""
    lines = structures.lines
    support = np.array([line.support_px for line in lines])
    splits = line_families(lines, frame_size, config.lines, hidden_px)

    def scored(some: list):
        hypotheses = split_hypotheses(some, support, pitch, frame_size, config.lines, config.max_hypotheses)
        return hypotheses, _scores(hypotheses, structures.scorer, frame_size, config.search, config.rescore_top,
                                   config.prescore_keep, config.prescore_thin)

    if len(splits) > 1:
        hypotheses, costs = scored(splits[:1])
        if _explains_well(costs, config):
            return hypotheses, costs, lambda: scored(splits)
    return (*scored(splits), None)


def _explains_well(costs: np.ndarray, config: CourtConfig) -> bool:
    """Whether a hypothesis of these map costs explains the map well (``explained_well_score``)."""
    return bool(len(costs)) and -float(costs.min()) >= config.explained_well_score


def _scores(hypotheses, scorer, frame_size, search: MaskSearchConfig, rescore_top: int, prescore_keep: int,
            prescore_thin: int) -> np.ndarray:
    """(K,) map costs of the hypotheses: all on every second template sample and marking point (when there are more
    than ``prescore_keep``, only the ``prescore_keep`` best on every ``prescore_thin``-th), the ``rescore_top`` best
    again in full (the others inf: they are not fitted)."""
    if not len(hypotheses):
        return np.zeros(0)
    H_px = pixel_homographies(hypotheses, frame_size)
    px_per_m = hypotheses.focal_n * (frame_size[0] / 2.0) * hypotheses.scale_m
    sign = hypotheses.sign
    kept = np.arange(len(H_px))
    if len(kept) > prescore_keep:
        rough = scorer.plane_costs(H_px, sign, px_per_m, search.coarse_hit_px, search.coarse_point_px,
                                   thin=prescore_thin, best=prescore_keep)
        kept = np.sort(np.argsort(rough, kind="stable")[:prescore_keep])
    costs = np.full(len(H_px), np.inf)
    costs[kept] = scorer.plane_costs(H_px[kept], sign[kept], px_per_m[kept], search.coarse_hit_px,
                                     search.coarse_point_px, thin=search.coarse_thin, best=rescore_top)
    top = np.argsort(costs, kind="stable")[:rescore_top]  # ties (the map's shares of whole counts) in order
    top = top[np.isfinite(costs[top])]
    fine = scorer.plane_costs(H_px[top], sign[top], px_per_m[top], search.score_hit_px, search.score_point_px)
    out = np.full(len(costs), np.inf)
    out[top] = fine
    return out


def court_reinit(detections, frame_size: tuple[int, int], curves: TemplateCurves) -> ReinitResult:
    """:func:`reinit_from_court` on a frame's detections (its marking map, marking points, field and player masks)."""
    return reinit_from_court(detections.marking_mask, detections.marking_points_px, frame_size, curves.pitch, curves,
                             detections.field_mask, player_mask=detections.player_mask,
                             motion_blur=detections.motion_blur)
