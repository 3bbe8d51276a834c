"""Repeated frames: the same image again (a frame-rate conversion's duplicate), told from a frame of its own."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.shots.repeats import RepeatConfig, repeat_grey, repeats, reduced_grey


def _frame(seed: int = 0, shift_px: float = 0.0, player_at: int | None = None) -> np.ndarray:
    """A 1280x720 grass frame with lines and a textured stand, the scene shifted right by shift_px (a pan)."""
    rng = np.random.default_rng(seed)
    image = np.zeros((720, 1280, 3), np.uint8)
    image[:] = (40, 140, 60)
    image[:180] = rng.integers(0, 255, (180, 1280, 3), dtype=np.uint8)  # a crowd
    for x in range(100, 1280, 300):
        cv2.line(image, (x, 720), (x + 200, 180), (235, 235, 235), 3)
    if player_at is not None:
        cv2.rectangle(image, (player_at, 400), (player_at + 20, 460), (30, 30, 200), -1)
    if shift_px:
        image = cv2.warpAffine(image, np.float32([[1, 0, shift_px], [0, 1, 0]]), (1280, 720),
                               borderMode=cv2.BORDER_REPLICATE)
    return image


def test_the_same_image_again_repeats_even_re_encoded():
    first = _frame(player_at=600)
    assert repeats(repeat_grey(first), repeat_grey(first.copy()))
    noisy = np.clip(first.astype(int) + np.random.default_rng(1).integers(-4, 5, first.shape), 0, 255).astype(np.uint8)
    assert repeats(repeat_grey(first), repeat_grey(noisy))  # compression noise of a few grey levels
    _, jpeg = cv2.imencode(".jpg", first, [cv2.IMWRITE_JPEG_QUALITY, 60])
    assert repeats(repeat_grey(first), repeat_grey(cv2.imdecode(jpeg, cv2.IMREAD_COLOR)))


def test_a_frame_of_its_own_does_not_repeat():
    first = _frame(player_at=600)
    assert not repeats(repeat_grey(first), repeat_grey(_frame(shift_px=1.0, player_at=600)))  # a pan of one pixel
    assert not repeats(repeat_grey(first), repeat_grey(_frame(seed=1, player_at=600)))  # the crowd moved
    assert not repeats(None, repeat_grey(first))  # the first frame
    assert not repeats(repeat_grey(first), repeat_grey(cv2.resize(first, (640, 480))))  # another size


def test_a_still_camera_with_one_player_moving_shows_nothing_new_for_the_camera():
    # Under half a percent of the image changed: the camera moved well under a pixel (a pan of one pixel changes
    # every edge), so the previous frame's camera is this frame's too.
    assert repeats(repeat_grey(_frame(player_at=600)), repeat_grey(_frame(player_at=640)))


def test_the_thresholds_are_the_configs():
    first = _frame(player_at=600)
    panned = repeat_grey(_frame(shift_px=1.0, player_at=600))
    assert repeats(repeat_grey(first), panned, RepeatConfig(max_changed_share=0.5))
    assert repeat_grey(first, RepeatConfig(work_width_px=320)).shape == (180, 320)


def test_nothing_repeats_when_the_share_is_zero():
    first = _frame(player_at=600)
    assert not repeats(repeat_grey(first), repeat_grey(first), RepeatConfig(max_changed_share=0.0))


def test_reduced_grey_from_the_working_image_is_the_frames_within_a_grey_level():
    """Made from the frame's area-averaged working image, the grey image has the same size and differs from the one
    made from the frame itself by under a grey level on average; a working image narrower than asked is not used."""
    rng = np.random.default_rng(3)
    frame = cv2.GaussianBlur(rng.integers(0, 256, (1080, 1920, 3), dtype=np.uint8), (0, 0), 2.0)
    working = cv2.resize(frame, (960, 540), interpolation=cv2.INTER_AREA)
    direct, via = reduced_grey(frame, 640), reduced_grey(frame, 640, working)
    assert via.shape == direct.shape == (360, 640)
    assert np.abs(via.astype(int) - direct.astype(int)).mean() < 1.0
    assert not np.array_equal(via, direct)  # it was made from the working image
    np.testing.assert_array_equal(reduced_grey(frame, 1280, working), reduced_grey(frame, 1280))
