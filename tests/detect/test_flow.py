"""Optical flow (broadtrack_graph.detect.flow) under shading that stays put in the frame."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.flow import FlowConfig, grid_flow, prepare

W, H = 640, 360


def _swept_frames(shift_px: int, blur_prev_px: int, blur_cur_px: int, vignetting: float):
    """Two frames of a faint grass-like texture, the second moved ``shift_px`` to the left, each smeared along
    the motion by its own box blur (a pan speeding up), both darkened towards the corners by the same lens."""
    rng = np.random.default_rng(11)
    texture = cv2.GaussianBlur(rng.normal(0.0, 1.0, (H, W + shift_px)).astype(np.float32), (0, 0), 2.0)
    texture = 110.0 + 8.0 * texture / texture.std()  # faint, as grass
    prev = cv2.blur(texture[:, :W], (blur_prev_px, 1))
    cur = cv2.blur(texture[:, shift_px:shift_px + W], (blur_cur_px, 1))
    yy, xx = np.mgrid[0:H, 0:W]
    radius2 = ((xx - W / 2) / (W / 2)) ** 2 + ((yy - H / 2) / (W / 2)) ** 2
    lens = 1.0 - vignetting * 0.5 * radius2
    to_image = lambda grey: cv2.cvtColor(np.clip(grey * lens, 0, 255).astype(np.uint8), cv2.COLOR_GRAY2BGR)
    return to_image(prev), to_image(cur)


def _median_error_px(prev, cur, config: FlowConfig, shift_px: int) -> tuple[float, int]:
    matches = grid_flow(prepare(prev, config), prepare(cur, config), W, H, config=config)
    error = matches.uv_cur_px[:, 0] - matches.uv_prev_px[:, 0] + shift_px
    return float(np.median(np.abs(error))), len(matches)


def test_flow_under_motion_blur_is_not_held_back_by_vignetting():
    config = FlowConfig(work_width_px=W, grid_step_px=24)
    raw = FlowConfig(work_width_px=W, grid_step_px=24, shading_sigma_px=0.0)
    prev, cur = _swept_frames(shift_px=24, blur_prev_px=15, blur_cur_px=21, vignetting=0.3)
    error, count = _median_error_px(prev, cur, config, 24)
    assert count > 200 and error < 0.8
    # Without the shading taken out, the lens's darkening (which stays put in the frame) holds the matches back.
    raw_error, raw_count = _median_error_px(prev, cur, raw, 24)
    assert raw_error > 1.5 * error and raw_count < count
    # ... which it does not without vignetting: the shading was the cause.
    clean_prev, clean_cur = _swept_frames(shift_px=24, blur_prev_px=15, blur_cur_px=21, vignetting=0.0)
    assert _median_error_px(clean_prev, clean_cur, raw, 24)[0] < 0.8


def test_flow_of_sharp_frames_is_the_same_with_the_shading_taken_out():
    prev, cur = _swept_frames(shift_px=6, blur_prev_px=1, blur_cur_px=1, vignetting=0.0)
    for sigma in (0.0, 32.0):
        error, count = _median_error_px(prev, cur, FlowConfig(work_width_px=W, grid_step_px=24, shading_sigma_px=sigma), 6)
        assert count > 200 and error < 0.1


def test_prepare_takes_the_repeat_tests_grey_unchanged():
    """The flow's working image made from the repeat test's grey (the same reduction) is the one made from the
    frame; a grey at another width is not taken."""
    from broadtrack_graph.shots.repeats import reduced_grey

    rng = np.random.default_rng(4)
    frame = rng.integers(0, 256, (1080, 1920, 3), dtype=np.uint8)
    config = FlowConfig()
    own = prepare(frame, config).grey
    assert np.array_equal(prepare(frame, config, reduced_grey(frame, config.work_width_px)).grey, own)
    assert np.array_equal(prepare(frame, config, reduced_grey(frame, 320)).grey, own)


def test_the_shading_is_taken_out_where_the_grey_image_is_first_read():
    """A prepared frame sent to another process before its grey image was read (the preparing process behind the
    tracking) takes the shading out there: the same image as read here, sent once, whichever side read it."""
    import pickle

    from broadtrack_graph.shots.repeats import reduced_grey

    rng = np.random.default_rng(5)
    frame = rng.integers(0, 256, (360, 640, 3), dtype=np.uint8)
    config = FlowConfig()
    unread, read = prepare(frame, config), prepare(frame, config)
    assert unread.shape == read.shape == (360, 640)
    shaded = read.grey
    assert not np.array_equal(shaded, reduced_grey(frame, config.work_width_px))  # the shading is out
    sent = pickle.loads(pickle.dumps(unread))
    assert np.array_equal(sent.grey, shaded) and sent.grey is sent.grey  # taken out once, then kept
    assert len(pickle.dumps(read)) < 1.2 * shaded.nbytes  # the grey image sent once, not beside the unshaded one
    raw = prepare(frame, FlowConfig(shading_sigma_px=0.0))
    assert np.array_equal(raw.grey, reduced_grey(frame, config.work_width_px))


def test_an_overlay_that_stays_put_while_the_camera_moves_is_left_out_of_the_flow():
    """A score bug pasted at the same place on both frames of a pan: its matches say 'no motion', against the
    homography every grass point follows; they are dropped (consensus_px 0: kept)."""
    prev, cur = _swept_frames(shift_px=8, blur_prev_px=1, blur_cur_px=1, vignetting=0.0)
    rng = np.random.default_rng(5)
    bug = cv2.cvtColor(rng.integers(0, 255, (90, 220), dtype=np.uint8), cv2.COLOR_GRAY2BGR)
    for frame in (prev, cur):
        frame[250:340, 40:260] = bug
    for consensus, expected_static in ((1.5, 0), (0.0, 10)):
        config = FlowConfig(work_width_px=W, grid_step_px=24, consensus_px=consensus)
        matches = grid_flow(prepare(prev, config), prepare(cur, config), W, H, config=config)
        motion = matches.uv_cur_px[:, 0] - matches.uv_prev_px[:, 0]
        static = int(np.sum(np.abs(motion) < 1.0))
        assert (static == 0) if expected_static == 0 else (static >= expected_static)
        assert np.sum(np.abs(motion + 8) < 0.5) > 150  # the grass's matches stay


def test_a_still_camera_keeps_every_match():
    prev, _ = _swept_frames(shift_px=0, blur_prev_px=1, blur_cur_px=1, vignetting=0.0)
    config = FlowConfig(work_width_px=W, grid_step_px=24)
    kept = grid_flow(prepare(prev, config), prepare(prev.copy(), config), W, H, config=config)
    everything = grid_flow(prepare(prev, config), prepare(prev.copy(), config), W, H,
                           config=FlowConfig(work_width_px=W, grid_step_px=24, consensus_px=0.0))
    assert len(kept) == len(everything) > 200
