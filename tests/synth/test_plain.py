"""The plain renderer: its markings from the Laws' dimensions land where the project's template projects them."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.synth.plain import PlainLook, draw_plain_look, marking_distance_m, render_plain, unpainted

W, H = 640, 360
# Clean: no players, blur, noise or compression; plain grass, white paint 12 cm wide.
LOOK = PlainLook(grass_bgr=(50.0, 130.0, 60.0), stripe_m=5.0, stripe_contrast=0.0, line_width_m=0.12,
                 paint_bgr=(255.0, 255.0, 255.0), crowd_block_px=4, players=0, lens_blur_px=0.0, motion_blur_px=0,
                 motion_angle_deg=0.0, noise_sigma=0.0, jpeg_quality=0, seed=1)


def _camera() -> Camera:
    # The main camera 20 m up, 45 m from the touchline, on the centre circle and the left half.
    return Camera.from_degrees(900.0, 0.0, -25.0, 70.0, 0.0, (0.0, 79.0, -20.0), W, H)


def test_distances_to_the_markings():
    x = np.array([0.0, 9.15, 41.5, 20.0, -20.0, 20.0, 52.0, 30.0])
    y = np.array([10.0, 0.0, 0.0, 10.0, -10.0, -10.0, 33.5, 0.0])
    distance, normal = marking_distance_m(x, y)
    # halfway line, centre circle, penalty spot (a disc), open grass (13.2 m to the circle; symmetric about both axes),
    # half a metre inside the corner (the corner arc's 1 m radius is closer than either line), the penalty arc
    # (outside the box only: 30 m is 11.5 m from the spot)
    assert np.allclose(distance[:3], 0.0)
    assert np.allclose(distance[3:6], np.hypot(20.0, 10.0) - 9.15)
    assert np.isclose(distance[6], 1.0 - np.hypot(0.5, 0.5)) and np.isclose(distance[7], 11.5 - 9.15)
    assert np.allclose(np.abs(normal[0]), (1.0, 0.0)) and np.allclose(np.abs(normal[6]), np.sqrt(0.5))
    assert np.allclose(np.linalg.norm(normal[[0, 1, 3, 4, 5, 6, 7]], axis=1), 1.0)


def test_the_paint_lies_on_the_projected_template_and_nowhere_else():
    camera = _camera()
    image = render_plain(camera, LOOK).astype(float).mean(axis=2)
    bare = render_plain(camera, unpainted(LOOK)).astype(float).mean(axis=2)
    pitch = PitchTemplate()
    samples = np.vstack([p for name, p in pitch.sample_uniform(0.25).items() if pitch.is_on_ground(name)])
    spots = np.array([[0.0, 0.0, 0.0], [41.5, 0.0, 0.0], [-41.5, 0.0, 0.0]])  # painted, not line classes
    uv, front = camera.project(np.vstack([samples, spots]))
    inside = front & (uv[:, 0] >= 2) & (uv[:, 0] < W - 2) & (uv[:, 1] >= 2) & (uv[:, 1] < H - 2)
    assert inside.sum() > 500
    px = np.rint(uv[inside]).astype(int)
    brighter = image[px[:, 1], px[:, 0]] - bare[px[:, 1], px[:, 0]]
    assert np.mean(brighter > 20.0) > 0.9  # the template's own samples are painted
    changed = np.abs(image - bare) > 1.0
    near = np.zeros((H, W), bool)
    for du in range(-3, 4):
        for dv in range(-3, 4):
            near[np.clip(px[:, 1] + dv, 0, H - 1), np.clip(px[:, 0] + du, 0, W - 1)] = True
    assert changed.any() and not (changed & ~near)[5:-5, 5:-5].any()  # and nothing else is


def test_a_look_renders_the_same_image_every_time_and_varies_between_looks():
    camera = _camera()
    looks = [draw_plain_look(np.random.default_rng(seed)) for seed in range(6)]
    assert np.array_equal(render_plain(camera, looks[0]), render_plain(camera, looks[0]))
    assert len({look.grass_bgr for look in looks}) == 6 and any(look.motion_blur_px for look in looks)
    blurred = replace(LOOK, motion_blur_px=15, motion_angle_deg=30.0)
    assert not np.array_equal(render_plain(camera, blurred), render_plain(camera, LOOK))


def test_a_clips_next_frames_keep_the_players_on_the_pitch_and_draw_their_noise_afresh():
    from broadtrack_graph.synth.plain import players_centre_m

    camera = _camera()
    look = replace(LOOK, players=12, noise_sigma=3.0)
    first = render_plain(camera, look)
    # Frame 0 with the players around where the camera looks is frame 0 as a single frame renders it.
    assert np.array_equal(first, render_plain(camera, look, frame=0, players_around_m=players_centre_m(camera)))
    again = render_plain(camera, look, frame=1)
    assert not np.array_equal(first, again)
    difference = first.astype(float) - again.astype(float)
    assert abs(difference.std() - np.sqrt(2.0) * 3.0) < 0.6  # two draws of the noise, nothing else changed
    # Panned 2 deg, the players stay on the ground point frame 0 put them around: drawn in the same place as on the
    # noiseless frame 0 once the view is turned back (their pixels in the turned view against the first one's).
    quiet = replace(look, noise_sigma=0.0)
    panned = camera.replace(pan_rad=camera.pan_rad + np.radians(2.0))
    around = players_centre_m(camera)
    with_players = render_plain(panned, quiet, frame=1, players_around_m=around)
    bare = render_plain(panned, replace(quiet, players=0), frame=1)
    drawn = np.abs(with_players.astype(float) - bare.astype(float)).sum(axis=2) > 30
    following = render_plain(panned, quiet, frame=1)  # the players around where the panned camera looks
    moved = np.abs(following.astype(float) - bare.astype(float)).sum(axis=2) > 30
    assert drawn.sum() > 200 and not np.array_equal(drawn, moved)
    ground, hits = panned.ground_intersection(np.argwhere(drawn)[:, ::-1].astype(float))
    assert hits.all() and np.median(np.hypot(*(ground[:, :2] - around).T)) < 30.0


def test_a_clips_crowd_stays_put_in_the_world_while_the_camera_turns():
    # Looking up over the far touchline: the crowd's blocks fill the top of the image.
    camera = Camera.from_degrees(900.0, 0.0, -10.0, 80.0, 0.0, (0.0, 79.0, -20.0), W, H)
    look = replace(LOOK, crowd_block_px=6)
    first = render_plain(camera, look)
    assert np.array_equal(first, render_plain(camera, look, crowd_camera=camera))  # frame 0 as a single frame
    # Turned by 12 px at the image centre: the crowd's pixels are frame 0's moved 12 px across the image (the pan
    # is about the vertical; near the image centre's row it moves the image along the row).
    shift = 12
    panned = camera.replace(pan_rad=camera.pan_rad + shift / camera.focal_px)
    turned = render_plain(panned, look, frame=1, crowd_camera=camera)
    rows = slice(H // 2 - 40, H // 2 - 20)
    assert not (first[rows, 100:-100] == np.array(LOOK.grass_bgr, np.uint8)).all(axis=2).any()  # crowd, no grass

    def mismatch(s: int) -> float:  # mean grey-level difference with the turned frame moved s px along the rows
        moved = turned[rows, 100 + s:W - 100 + s].astype(float)
        return float(np.abs(moved - first[rows, 100:-100].astype(float)).mean())

    best = min(range(-20, 21), key=mismatch)
    assert abs(abs(best) - shift) <= 1 and mismatch(best) < 5
    # Without crowd_camera the blocks stay where the image has them.
    still = render_plain(panned, look, frame=1)
    assert np.array_equal(still[rows, 100:-100], first[rows, 100:-100])
