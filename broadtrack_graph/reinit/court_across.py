"""Court-model hypotheses of a family of image lines meeting at a vanishing point and one line across it. No I/O.

Three lines of one direction and one across fix the ground homography (:mod:`.court_pencil`), two and one fix a
level camera's (:mod:`.court_level`); both are formed the same way from the map's lines:
:func:`family_and_across_hypotheses` takes the best voted vanishing points as families, and asks each module for the
homographies of every choice of the family's lines with every line across.

Image coordinates are normalised as in :mod:`.court_lines`; pitch frame in metres, z down.
"""

from __future__ import annotations

import itertools

import numpy as np

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_families import CourtLineConfig, distinct_sets, vanishing_votes
from broadtrack_graph.reinit.court_lines import (
    PlaneHypotheses,
    cameras_from_homographies,
    concatenate,
    pitch_line_offsets,
)


def family_and_across_hypotheses(lines: list, frame_size, pitch: PitchTemplate, min_lines: int, families: int,
                                 max_family_lines: int, max_across_lines: int, homographies_of,
                                 config: CourtLineConfig = CourtLineConfig(), hidden_px: np.ndarray | None = None
                                 ) -> PlaneHypotheses:
    """The cameras of a family of ``min_lines`` image lines meeting at a vanishing point and one line across them
    (:mod:`.court_pencil`: three, :mod:`.court_level`: two), gated by :func:`cameras_from_homographies`.

    The ``families`` best voted distinct vanishing points that ``min_lines`` lines or more point at
    (:func:`~.court_families.distinct_sets`) are each taken as a family: its best supported ``max_family_lines`` lines,
    ``min_lines`` at a time, with the best supported ``max_across_lines`` solid lines not pointing at it, each family as
    either pitch direction. ``homographies_of(family_n (min_lines, 3), across_n (n, 3), family_offsets_m,
    across_offsets_m, family_is_x)`` gives their homographies (normalised coordinates; ``family_is_x``: the family is
    the y = c direction).

    Args:
        lines: the straight markings of the map (frame pixels, :class:`~broadtrack_graph.detect.marking_structures.
            ImageLine`).
        hidden_px: (L,) each line's length the players hide (:func:`~.court_families.vanishing_votes`).
    """
    votes = vanishing_votes(lines, frame_size, config, hidden_px)
    if votes is None or len(votes.lines_n) < min_lines + 1:
        return concatenate([])
    support = votes.support_px
    offsets = pitch_line_offsets(pitch)  # (y = c offsets, x = c offsets)
    enough = votes.meets.sum(axis=1) >= min_lines
    homographies = []
    for family in distinct_sets(votes.meets[enough], votes.meets[enough] @ support, families):
        members = np.nonzero(family)[0]
        members = members[np.argsort(-support[members])][:max_family_lines]
        others = np.nonzero(votes.solid & ~family)[0]
        others = others[np.argsort(-support[others])][:max_across_lines]
        if len(members) < min_lines or not len(others):
            continue
        for chosen in itertools.combinations(members, min_lines):
            for family_is_x in (True, False):  # the family along x (the y = c lines) or along y
                homographies.append(homographies_of(votes.lines_n[list(chosen)], votes.lines_n[others],
                                                    offsets[0 if family_is_x else 1], offsets[1 if family_is_x else 0],
                                                    family_is_x))
    stacked = np.concatenate(homographies) if homographies else np.zeros((0, 3, 3))
    return cameras_from_homographies(stacked, frame_size, pitch, config)
