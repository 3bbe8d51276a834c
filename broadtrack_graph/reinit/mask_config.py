"""Settings of the weight-free re-initialisation (:func:`~broadtrack_graph.reinit.mask.reinit_from_mask`).

Shared by its parts: line-pair and circle hypotheses, the map scorer and the label-and-fit rounds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import MarkingStructureConfig
from broadtrack_graph.reinit.positions import FAR_MAIN_POSITIONS_W


@dataclass(frozen=True)
class RefineSchedule:
    """Label-and-fit rounds of :func:`reinit_from_mask` (sizes as shares of the frame width).

    Each round names the marking points by the nearest projected class within its gate and
    fits :func:`fit_camera_to_lines` with Cauchy scale ``clip(cauchy_per_gate * gate,
    cauchy_min_per_width, cauchy_max_per_width)``; the rounds before the last stop at a looser
    relative cost decrease.
    """

    gates_per_width: tuple[float, ...]  # labelling gate of each round
    iterations: int  # LM iterations per round
    cauchy_per_gate: float = 0.0
    cauchy_min_per_width: float = 1.0 / 960  # 1 px at 960, 2 px at 1920
    cauchy_max_per_width: float = 1.0 / 960
    k1_free_from_round: int = 2  # k1 is held at 0 before this round (and free in the last round)
    # A round before the last stops once an LM step lowers its cost by less than this share: the next round names
    # the points again with a smaller gate, so converging further moves nothing it keeps. The last round stops at
    # LineFitConfig.min_relative_decrease.
    early_round_min_relative_decrease: float = 1e-3


TIGHT_SCHEDULE = RefineSchedule((0.02, 0.008, 0.004), 20)
"""Small robust scale throughout: stays in the basin of a close hypothesis, ignores clutter near markings."""

WIDE_SCHEDULE = RefineSchedule((0.025, 0.015, 0.01, 0.006, 0.004), 10, cauchy_per_gate=1.0 / 3.5,
                               cauchy_max_per_width=0.003)
"""A robust scale that starts wide: pulls in a hypothesis 10-20 px off (e.g. a tripod guess several metres off)."""


@dataclass(frozen=True)
class MaskSearchConfig:
    """Settings of :func:`~broadtrack_graph.reinit.mask.reinit_from_mask`.

    Pixel sizes are at the working width named in each group (``structures.line_work_width_px``
    for the map's lines and ellipses, ``score_work_width_px`` for the scores), so they do not
    change with the frame size; ``*_per_width`` are shares of the frame width.
    """

    # Straight markings and ellipses of the map (marking_lines, marking_ellipses; max_ellipses 0: no circle hypotheses).
    structures: MarkingStructureConfig = MarkingStructureConfig()
    # The cameras putting two straight markings on two pitch lines (line_pair_cameras).
    line_focal_count: int = 80  # focal lengths tried per pair (geometric over line_focal_range_per_width)
    line_focal_range_per_width: tuple[float, float] = (0.5, 12.0)  # f / W: about 90 to 5 deg of field of view
    line_angle_tol_deg: float = 2.0  # angle between the two viewing planes vs the pitch lines' planes
    line_roll_tol_deg: float = 3.0  # |roll| of the aligned camera (the operator keeps roll about 0)
    line_margin_m: float = 3.0  # a marking's ends must fall on the painted line, within this margin
    tilt_range_deg: tuple[float, float] = (40.0, 95.0)  # accepted tilts of line-pair and circle cameras
    # The cameras putting a pitch circle on an ellipse of the map (ellipse_cameras, circle_hypotheses).
    ellipse_focal_factors: tuple[float, ...] = tuple(np.geomspace(0.85, 1.3, 13))  # f tried around the estimate
    ellipse_fit_top_k: int = 4  # the closest rough circle cameras fitted to their ellipse's points ...
    ellipse_fit_points: int = 120  # ... (at most this many)
    # Scores of the hypotheses: -F_beta of precision and recall (MapScorer), at score_work_width_px.
    score_work_width_px: int = 640
    score_cap_px: float = 12.0  # distance transform cap
    score_template_step_m: float = 1.0  # template sampling
    score_hit_px: float = 2.0  # a template sample this close to a marking pixel is found (recall) ...
    score_point_px: float = 3.0  # ... a marking point this close to the projected template is explained (precision)
    score_min_template_px: float = 100.0  # recall denominator floor (working pixels of template)
    score_max_points: int = 200  # marking points used for the precision (evenly subsampled)
    score_beta: float = 1.0
    coarse_hit_px: float = 3.0  # tolerances of the first scoring of all line-pair cameras ...
    coarse_point_px: float = 5.0
    coarse_thin: int = 2  # ... on every second template sample and marking point
    polish_top_k: int = 24  # the best distinct line-pair cameras per focal point are moved along f ...
    polish_focal_steps: int = 9  # ... over one step of the focal grid either side
    distinct_per_width: float = 0.02  # hypotheses closer than this in the image count as one
    other_position_factor: float = 0.95  # scores at focal points other than the first candidate count this much
    poor_score: float = 0.35  # when no hypothesis at the default tripods scores this well, these are tried too:
    far_positions_w: tuple[tuple[float, float, float], ...] = FAR_MAIN_POSITIONS_W
    # Local polish of the best distinct hypotheses on the map score (polish_locally): pan, tilt and f moved
    # in a pattern search whose step shifts the image by this share of the width, halved down to the minimum.
    local_polish_top_k: int = 12  # 0: off
    local_polish_step_per_width: float = 0.03
    local_polish_min_step_per_width: float = 0.002
    # Refinement: name the marking points by the nearest projected class, fit, shrink the gate (RefineSchedule).
    refine_top_k: int = 6  # at most this many distinct hypotheses are refined (best score first) ...
    refine_cost_share: float = 0.88  # ... after the first, only those scoring this share of its score ...
    max_fits: int = 5  # ... with at most this many label-and-fit runs in all ...
    accept_fit_score: float = 0.6  # ... stopping once a fit scores this (fit score below)
    fit_switch_margin: float = 0.1  # within one search: a later hypothesis replaces the best-scoring one when its fit score is this higher
    fit_template_step_m: float = 0.5  # the fit score: the score with a denser template, more points
    fit_max_points: int = 1000  # and tolerances of about 2 and 3 px at 1920
    fit_hit_px: float = 0.7
    fit_point_px: float = 1.0
    schedule: RefineSchedule = TIGHT_SCHEDULE  # the fit of every refined hypothesis
    wide_schedule: RefineSchedule | None = WIDE_SCHEDULE  # also run (the better fit score kept) on hypotheses
    wide_below_score: float = 0.5  # scoring below this (the tripod guess may be metres off); None: never
    position_sigma_m: float = 3.0  # prior on the focal point around the hypothesis's
    min_classes_free_position: int = 3  # with fewer named classes the fit holds the focal point and k1
    sigma_k1: float = 0.05  # prior on k1 around 0 (few far markings leave k1 and f entangled)
    max_fit_points: int = 400  # marking points used by the label-and-fit rounds (evenly subsampled)
