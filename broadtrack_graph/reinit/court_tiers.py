"""The court model's later tiers: the hypotheses tried after the straight markings'. No I/O.

Each tier is a source of ground homographies (pitch metres -> normalised image points), decomposed into cameras and
gated as the lines' are (:func:`~.court_lines.cameras_from_homographies`): three lines of one direction and one across
(:mod:`.court_pencil`), a circle's ellipse with a line across it or with a touchline (:mod:`.court_circle`), the same
on the ellipses fitted again on the markings' centre points (:mod:`~broadtrack_graph.detect.ellipse_refit`), and last
two lines of one direction and one across with the camera level (:mod:`.court_level`) and a circle's arc rectified
under the camera model with its chord or with a line of each direction beside it (:mod:`.court_arcs`,
:mod:`.court_arc_corners`). :func:`~.court.reinit_from_court` decides when each joins.

Conventions: pitch frame in metres, origin at the centre spot, z down.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_ellipses import outline_in_image
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_arc_corners import arc_corner_homographies, circle_corners
from broadtrack_graph.reinit.court_arcs import arc_line_homographies, arc_points
from broadtrack_graph.reinit.court_circle import (
    circle_line_homographies,
    circle_pole_homographies,
    pitch_circle_chords,
)
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.court_families import normalised_lines
from broadtrack_graph.reinit.court_level import level_hypotheses
from broadtrack_graph.reinit.court_lines import PlaneHypotheses, cameras_from_homographies, concatenate
from broadtrack_graph.reinit.court_pencil import pencil_hypotheses


@dataclass(frozen=True)
class Tier:
    """A source of hypotheses tried after the straight markings'.

    hypotheses: the call giving them (an empty set when its markings are missing).
    last_resort: joined only once the first fits are in, fitted apart, and its camera taken only with a constraint to
        spare (the level cameras' and the arcs': two lines and one, or a short arc, fix a camera exactly but poorly).
    min_confidence: its camera is taken only this confident at least (formed from fewer markings than fix a camera
        with nothing assumed, it lays itself on them whether right or not).
    """

    hypotheses: Callable[[], PlaneHypotheses]
    last_resort: bool = False
    min_confidence: float = 0.0


def later_tiers(structures, frame_size, pitch: PitchTemplate, config: CourtConfig,
                hidden_px: np.ndarray | None = None) -> list[Tier]:
    """The hypotheses tried after the straight markings', in order (:class:`Tier`): three
    lines of one direction and one across (a zoomed goal mouth), a circle with the line across it, the centre circle
    with a touchline (more hypotheses, and looser), a circle with the line across it again on the ellipses and arcs
    fitted again on the centre points; then, as tiers of last resort, two lines of one direction and one across with
    the camera level (a smeared frame's lines along its smear, a narrow view's corner of the penalty area; its camera
    taken only at ``exact_fit_confidence``: two lines and one, with the roll assumed, fix it exactly) and the arcs
    rectified under the camera model."""
    lines = structures.lines

    def pencil():
        if len(lines) < 4:
            return concatenate([])
        return pencil_hypotheses(lines, frame_size, pitch, config.pencil, config.lines, hidden_px)

    def level():
        if len(lines) < 3:
            return concatenate([])
        return level_hypotheses(lines, frame_size, pitch, config.level, config.lines, hidden_px)

    def circles(across: bool, refitted: bool = False):
        if not lines:
            return concatenate([])
        # An arc's piece fitted alone and an ellipse fitted through it and another piece are two estimates of one
        # circle's image, a few per cent apart on a short arc: both are tried. Each fitted again on the markings'
        # centre points is a third, a source of their own (tried last: one of them scoring best on the map does not
        # take the others' place).
        ellipses = structures.refitted_ellipses() if refitted else structures.every_ellipse()
        return circle_hypotheses(ellipses, lines, frame_size, pitch, config, across)

    def arcs():
        # A circle's arc and its chord with the camera model asked first (a short arc's free ellipse is a poor
        # estimate of its circle's image): :mod:`.court_arcs`.
        if not lines:
            return concatenate([])
        points = arc_points(structures.every_ellipse(), structures.points_px, lines, frame_size[0], config.arc)
        focal_range_n = tuple(2.0 * v for v in config.lines.focal_range_per_width)
        chords = pitch_circle_chords(pitch)
        found = arc_line_homographies(points, lines, frame_size, chords, focal_range_n, config.arc)
        # ... and with one line of each direction beside it, across it or not (:mod:`.court_arc_corners`)
        corners = circle_corners(pitch, chords, config.arc_corner.max_line_share)
        found = np.concatenate([found, arc_corner_homographies(points, lines, frame_size, corners, focal_range_n,
                                                               config.arc.arc_band_px, config.arc_corner)])
        return cameras_from_homographies(found, frame_size, pitch, config.lines)

    return [Tier(pencil), Tier(lambda: circles(True)), Tier(lambda: circles(False)),
            Tier(lambda: circles(True, refitted=True)),
            Tier(level, last_resort=True, min_confidence=config.exact_fit_confidence), Tier(arcs, last_resort=True)]


def circle_hypotheses(ellipses, lines, frame_size, pitch: PitchTemplate, config: CourtConfig, across: bool):
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
