"""Cut and dissolve detection (broadtrack_graph.shots.cuts) on synthetic sequences."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.shots.cuts import CutDetector


def panning_clip(seed: int, frames: int, colour, size=(180, 320)) -> list[np.ndarray]:
    """A textured scene of one dominant colour, panned 2 px per frame."""
    rng = np.random.default_rng(seed)
    h, w = size
    base = np.clip(np.array(colour, float) + rng.normal(0, 25, (h, w + 2 * frames, 3)), 0, 255)
    base = base.astype(np.uint8)
    base[:, ::40] = 255  # vertical lines to follow
    return [np.ascontiguousarray(base[:, 2 * t:2 * t + w]) for t in range(frames)]


def cuts_of(frames) -> list[tuple[int, str]]:
    detector = CutDetector()
    out = []
    for i, image in enumerate(frames):
        result = detector.update(image)
        if result.cut and i:
            out.append((i, result.kind))
    return out


def test_a_hard_cut_between_two_clips_is_found_and_nothing_else():
    a = panning_clip(1, 30, (60, 140, 60))  # grass-like
    b = panning_clip(2, 30, (120, 90, 160))  # crowd-like
    assert cuts_of(a + b) == [(30, "hard")]
    assert cuts_of(a) == []


def test_a_dissolve_is_found_once_near_its_end():
    a = panning_clip(1, 30, (60, 140, 60))
    b = panning_clip(2, 60, (120, 90, 160))
    blend = [((1 - t / 20) * a[-1].astype(float) + (t / 20) * b[t].astype(float)).astype(np.uint8)
             for t in range(1, 20)]
    found = cuts_of(a + blend + b[20:])
    assert len(found) == 1, found
    index, kind = found[0]
    assert kind in ("dissolve", "hard") and 30 <= index < 50  # one boundary inside the blend


def test_a_short_cut_away_and_back_gives_two_cuts():
    a = panning_clip(1, 30, (60, 140, 60))
    b = panning_clip(2, 3, (120, 90, 160))
    assert cuts_of(a[:15] + b + a[15:]) == [(15, "hard"), (18, "hard")]
