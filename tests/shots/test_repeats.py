"""Repeated frames: the same image again (a frame-rate conversion's duplicate), told from a frame of its own."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.shots.repeats import RepeatConfig, reduced_grey, repeat_grey, repeats


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
    assert repeats(repeat_grey(first), panned, RepeatConfig(max_changed_share=0.5, max_shift_px=1.0))
    assert not repeats(repeat_grey(first), panned, RepeatConfig(max_changed_share=0.5))  # moved 0.5 px at 640
    assert repeat_grey(first, RepeatConfig(work_width_px=320)).shape == (180, 320)


def test_nothing_repeats_when_the_share_is_zero():
    first = _frame(player_at=600)
    assert not repeats(repeat_grey(first), repeat_grey(first), RepeatConfig(max_changed_share=0.0))


def test_reduced_grey_is_the_same_with_or_without_the_working_image():
    """A 1920 px frame is area-averaged to 960 px first, whether the detector's working image is given or made here
    (the tracker's two routes, with a detector and from a detections file, get the same flow); the result differs
    from one grey-then-area step by under a grey level on average. A narrower frame takes one step."""
    rng = np.random.default_rng(3)
    frame = cv2.GaussianBlur(rng.integers(0, 256, (1080, 1920, 3), dtype=np.uint8), (0, 0), 2.0)
    working = cv2.resize(frame, (960, 540), interpolation=cv2.INTER_AREA)
    made, given = reduced_grey(frame, 640), reduced_grey(frame, 640, working)
    np.testing.assert_array_equal(made, given)
    one_step = cv2.resize(cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY), (640, 360), interpolation=cv2.INTER_AREA)
    assert given.shape == (360, 640)
    assert 0 < np.abs(given.astype(int) - one_step.astype(int)).mean() < 1.0
    narrow = frame[:720, :1280]
    np.testing.assert_array_equal(
        reduced_grey(narrow, 640),
        cv2.resize(cv2.cvtColor(narrow, cv2.COLOR_BGR2GRAY), (640, 360), interpolation=cv2.INTER_AREA))


def test_a_slow_pan_over_bare_grass_does_not_repeat():
    # A narrow view of mown grass and one thin line panned by a pixel (half a pixel at the test's 640 px): under half
    # a percent of the image changes, but the whole image moved.
    def grass(shift_px: float, seed: int = 0) -> np.ndarray:
        x = np.arange(1280, dtype=float) + shift_px
        stripes = np.where(np.floor(x / 160.0) % 2 == 0, 1.0, 0.93)
        image = np.zeros((720, 1280, 3), np.float32)
        image[:] = np.array([45.0, 140.0, 60.0]) * stripes[None, :, None]
        line = np.clip(1.5 - np.abs(x - 700.0), 0.0, 1.0)  # a 2 px line across the image at x = 700
        image = image * (1 - line[None, :, None]) + 230.0 * line[None, :, None]
        noise = np.random.default_rng(seed).normal(0.0, 1.5, image.shape)
        return np.clip(image + noise, 0, 255).astype(np.uint8)

    first, panned = repeat_grey(grass(0.0)), repeat_grey(grass(1.0, seed=1))
    changed = (cv2.absdiff(first, panned) > RepeatConfig().change_grey_levels).mean()
    assert changed < RepeatConfig().max_changed_share
    assert not repeats(first, panned)
    _, jpeg = cv2.imencode(".jpg", grass(0.0), [cv2.IMWRITE_JPEG_QUALITY, 70])
    assert repeats(first, repeat_grey(cv2.imdecode(jpeg, cv2.IMREAD_COLOR)))  # the same image again, re-encoded
