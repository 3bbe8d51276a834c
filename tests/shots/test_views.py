"""View classification (broadtrack_graph.shots.views) on synthetic frames."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.shots.segmenter import ShotSegmenter
from broadtrack_graph.shots.views import VIEW_CLOSE_UP, VIEW_CROWD, VIEW_MAIN, classify_view, row_ends


def grass(h=360, w=640, seed=0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    image = np.clip(np.array([50, 140, 60], float) + rng.normal(0, 8, (h, w, 3)), 0, 255).astype(np.uint8)
    return image


def wide_view() -> np.ndarray:
    image = grass()
    image[:60] = (90, 80, 120)  # stands at the top
    cv2.line(image, (0, 300), (640, 250), (235, 235, 235), 2)  # a touchline
    for x, y in ((100, 150), (300, 200), (500, 120), (420, 260)):
        cv2.rectangle(image, (x, y), (x + 8, y + 25), (30, 30, 200), -1)  # small players
    return image


def test_the_wide_view_is_main():
    result = classify_view(wide_view())
    assert result.kind == VIEW_MAIN, result.reason


def test_a_frame_without_grass_is_crowd():
    rng = np.random.default_rng(3)
    stands = rng.integers(0, 255, (360, 640, 3)).astype(np.uint8)
    stands[..., 1] //= 3  # little green
    result = classify_view(stands)
    assert result.kind == VIEW_CROWD and result.grass_share < 0.25


def test_a_huge_player_blob_on_grass_is_a_close_up():
    image = grass()
    cv2.ellipse(image, (320, 260), (90, 200), 0, 0, 360, (160, 60, 30), -1)  # a body filling the height
    cv2.circle(image, (320, 70), 45, (120, 150, 200), -1)
    result = classify_view(image)
    assert result.kind == VIEW_CLOSE_UP, result.reason


def test_a_caption_bar_on_grass_is_not_a_close_up():
    image = wide_view()
    image[280:330, 100:540] = (20, 20, 20)  # a wide, low caption graphic
    assert classify_view(image).kind == VIEW_MAIN


def test_the_segmenter_keeps_a_shot_s_majority_view():
    segmenter = ShotSegmenter()
    close = grass()
    cv2.ellipse(close, (320, 260), (90, 200), 0, 0, 360, (230, 200, 180), -1)  # a light shirt
    kinds = [segmenter.update(i, wide_view()).kind for i in range(6)]
    kinds += [segmenter.update(6 + i, close).kind for i in range(6)]
    assert kinds[:6] == [VIEW_MAIN] * 6 and kinds[6:] == [VIEW_CLOSE_UP] * 6
    # The shot step does not know the pitch camera: the tracker names it (place_shot).
    assert [(s.start, s.end, s.kind, s.camera_id) for s in segmenter.shots] == [(0, 6, "main", None),
                                                                                (6, 12, "close-up", None)]


def _without_cuts(segmenter: ShotSegmenter) -> ShotSegmenter:
    """The segmenter with a cut step that finds no cut (a dissolve it missed)."""
    from types import SimpleNamespace

    segmenter.cuts = SimpleNamespace(update=lambda image: SimpleNamespace(cut=False, kind=None))
    return segmenter


def test_a_pitch_view_after_a_missed_cut_starts_its_own_shot():
    segmenter = _without_cuts(ShotSegmenter())
    close = grass()
    cv2.ellipse(close, (320, 260), (90, 200), 0, 0, 360, (230, 200, 180), -1)  # a light shirt
    for i in range(10):
        segmenter.update(i, close)
    # The close-up melts into the main camera's view without a cut the cut step sees (same grass colours).
    kinds = [segmenter.update(10 + i, wide_view()) for i in range(12)]
    assert [s.kind for s in segmenter.shots] == ["close-up", "main"]
    first, second = segmenter.shots
    n = segmenter.config.view_change_frames
    assert (first.start, first.end, first.views) == (0, 10, {"close-up": 10}) and second.boundary == "view"
    assert second.start == 10 and second.end == 22 and second.views == {"main": 12}
    assert kinds[n - 1].cut and kinds[n - 1].shot_index == 1 and not kinds[n - 1].is_other_view
    assert all(k.is_other_view for k in kinds[:n - 1])  # those frames were already judged in the close-up shot


def test_a_main_shot_is_not_split_by_frames_taken_for_close_ups():
    segmenter = _without_cuts(ShotSegmenter())
    close = grass()
    cv2.ellipse(close, (320, 260), (90, 200), 0, 0, 360, (230, 200, 180), -1)
    for i in range(10):
        segmenter.update(i, wide_view())
    kinds = [segmenter.update(10 + i, close) for i in range(12)]
    assert len(segmenter.shots) == 1 and all(not k.cut for k in kinds)


def test_place_shot_names_the_pitch_camera():
    from broadtrack_graph.types.shot import Shot, place_shot

    pitch = Shot(0, 10, "main", None)
    assert (place_shot(pitch, "main").kind, place_shot(pitch, "main").camera_id) == ("main", "main")
    assert place_shot(pitch, "high-corner-1").kind == "other-camera"
    assert (place_shot(pitch, None).kind, place_shot(pitch, None).camera_id) == ("pitch", None)
    assert place_shot(Shot(10, 20, "close-up", None), None) == Shot(10, 20, "close-up", None)
    # A shot read as a close-up whose markings placed a camera anyway is a pitch shot; its views say how it was read.
    read = Shot(10, 20, "close-up", None, views={"close-up": 10})
    assert place_shot(read, "high-behind-1") == Shot(10, 20, "other-camera", "high-behind-1", views={"close-up": 10})


def test_row_ends_give_the_same_filled_hull_as_every_pixel():
    """The convex hull of each row's two end pixels fills exactly the region the hull of all the pixels fills."""
    rng = np.random.default_rng(7)
    for trial in range(40):
        mask = np.zeros((90, 160), np.uint8)
        for _ in range(int(rng.integers(1, 6))):  # a few random convex and thin blobs, as grass regions cut by graphics
            centre = tuple(int(v) for v in rng.integers(0, (160, 90)))
            axes = tuple(int(v) for v in rng.integers(1, 60, 2))
            cv2.ellipse(mask, centre, axes, float(rng.uniform(0, 180)), 0, 360, 1, -1)
        mask[rng.random(mask.shape) < 0.05] ^= 1  # speckle: lone pixels and holes
        ys, xs = np.nonzero(mask)
        every = np.zeros_like(mask)
        cv2.fillConvexPoly(every, cv2.convexHull(np.column_stack([xs, ys]).astype(np.int32)), 1)
        ends = np.zeros_like(mask)
        cv2.fillConvexPoly(ends, cv2.convexHull(row_ends(mask > 0)), 1)
        np.testing.assert_array_equal(ends, every, err_msg=f"trial {trial}")
    assert row_ends(np.zeros((4, 5), bool)).shape == (0, 2)
