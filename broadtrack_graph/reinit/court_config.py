"""Settings of the court model (:func:`~broadtrack_graph.reinit.court.reinit_from_court`): its hypotheses, their
scoring, the fits and the judging of the camera kept. No I/O."""

from __future__ import annotations

from dataclasses import dataclass

from broadtrack_graph.detect.marking_structures import MarkingStructureConfig
from broadtrack_graph.reinit.court_arc_corners import ArcCornerConfig
from broadtrack_graph.reinit.court_arcs import CourtArcConfig
from broadtrack_graph.reinit.court_circle import CourtCircleConfig
from broadtrack_graph.reinit.court_families import CourtLineConfig
from broadtrack_graph.reinit.court_level import CourtLevelConfig
from broadtrack_graph.reinit.court_pencil import CourtPencilConfig
from broadtrack_graph.reinit.mask_config import MaskSearchConfig, RefineSchedule


@dataclass(frozen=True)
class CourtConfig:
    """Settings of :func:`reinit_from_court` (pixels at the frame size unless stated)."""

    # the hypotheses of the straight markings (and their gates); 16 splits of the lines: a banner's or a board's
    # edges make splits of their own that can take more of the lines' support than the pitch's
    lines: CourtLineConfig = CourtLineConfig(max_splits=16)
    # the circles' hypotheses (a circle with its chord, the centre circle with a touchline)
    circle: CourtCircleConfig = CourtCircleConfig()
    # a circle's arc and its chord, the camera model asked first (tried last)
    arc: CourtArcConfig = CourtArcConfig()
    # ... and an arc with one line of each direction, across it or not (tried with it)
    arc_corner: ArcCornerConfig = ArcCornerConfig()
    # three lines of one direction and one across (tried with the circles)
    pencil: CourtPencilConfig = CourtPencilConfig()
    # two lines of one direction and one across, the camera level (a tier of last resort, before the arcs')
    level: CourtLevelConfig = CourtLevelConfig()
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
    fit_tie_cost: float = 0.005  # ... and after a fit scoring search.accept_fit_score, only those whose map cost is
    #                              within this of its hypothesis's: hypotheses one map explains alike (the members of
    #                              a circle-and-line family, whose images of both are the same) are all fitted
    look_further_below: float = 0.9  # a camera kept under this (the tracker's certain_confidence) does not settle the
    #                                  frame: the later tiers not joined yet are fitted too, and a fit of theirs more
    #                                  confident by confidence_margin replaces it
    confidence_margin: float = 0.1  # a fit this much more confident than the best scoring one replaces it (the
    #                                 margin a new camera needs to replace a chain's:
    #                                 TrackingConfig.reinit_switch_margin)
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
    # A narrow view (f at least narrow_view_focal_per_width of the width: about 37 deg across or less) is nearly affine:
    # its distance and focal length trade off, and a fit can stop metres off along its line of sight with every
    # marking in view drawn a few pixels off. The camera returned under narrow_view_walk_below confident is fitted
    # again from starts at these factors of its distance, and the most confident fit kept (reinit.court_depth)
    narrow_view_focal_per_width: float = 1.5
    narrow_view_walk_below: float = 0.9
    narrow_view_depth_factors: tuple[float, ...] = (0.69, 0.83, 1.2, 1.44)
    # the camera returned, when polish_from confident (the tracker's court bar: taken at any bar), fitted once more
    # on up to polish_points marking points (the hypotheses' fits take search.max_fit_points), with labelling gates
    # for a camera already within a few pixels; kept when judged as every camera is and still polish_from confident
    polish_from: float = 0.7
    polish_points: int = 1500
    polish_schedule: RefineSchedule = RefineSchedule((0.006, 0.004, 0.003), 20)
    refit_top: int = 32  # the best hypotheses solved again on every straight marking they explain ...
    refit_min_lines: int = 4  # ... when they explain this many (both directions among them) ...
    refit_gate_per_width: float = 0.02  # ... each with both ends within this share of the width of its pitch line
    rescore_top: int = 64  # hypotheses scored coarsely first (every second sample), these best ones again in full
    prescore_keep: int = 256  # over this many hypotheses, all are scored on every prescore_thin-th template sample
    #                           and marking point first, these best go on (four times rescore_top: the best of that
    #                           rough pass hold the best of every second sample, docs/BENCHMARKS.md)
    prescore_thin: int = 8
    # a hypothesis scoring this on the map explains it well: the splits of the lines after the likeliest, and each
    # later tier (the circles first), are tried only while none before it does
    explained_well_score: float = 0.6
    centre_circle_min_coverage: float = 0.7  # map pixels per pixel of outline in view of an ellipse taken as the
    #                                          centre circle beside a touchline (painted all round; an arc is not)
