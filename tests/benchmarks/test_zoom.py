"""``bench real --zoom``: a clip as a longer lens shows it, the camera that sees it, and the video section on it."""

from __future__ import annotations

import argparse
import math

import cv2
import numpy as np
import pytest

from broadtrack_graph.benchmarks.clip_copy import write_copy
from broadtrack_graph.benchmarks.zoom import (
    camera_agreement,
    cut_figures,
    determinable_figures,
    parse_zoom,
    write_zoom_cut,
    zoom_change,
    zoom_frame,
    zoom_label,
    zoomed_camera,
    zoomed_size,
)
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate


def test_the_zoom_is_a_number_over_one():
    assert parse_zoom("2") == 2.0 and parse_zoom("1.5") == 1.5
    assert zoom_label(2.0) == "zoom2" and zoom_label(1.5) == "zoom1.5"
    for bad in ("1", "0.5", "9", "two", "nan"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_zoom(bad)


def test_the_zoomed_frame_is_the_frame_centre_pixel_for_pixel():
    image = np.random.default_rng(1).integers(0, 256, (1080, 1920, 3), dtype=np.uint8)
    assert zoomed_size(1920, 1080, 2.0) == (960, 540) and zoomed_size(1280, 720, 3.0) == (426, 240)
    assert zoomed_size(854, 480, 1.5) == (570, 320)
    zoomed = zoom_frame(image, 3.0)
    assert zoomed.shape == (360, 640, 3) and zoomed.flags["C_CONTIGUOUS"]
    np.testing.assert_array_equal(zoomed, image[360:720, 640:1280])


def test_the_zoomed_camera_draws_the_pitch_where_the_frame_crop_shows_it():
    camera = Camera.from_degrees(focal_px=2600.0, pan_deg=12.0, tilt_deg=78.0, roll_deg=0.3,
                                 position_m=[-4.0, 62.0, -16.0], width_px=1920, height_px=1080, k1=0.08)
    points = np.vstack(list(PitchTemplate().sample_uniform(1.0).values()))
    for zoom in (1.5, 2.0, 3.0):
        zoomed = zoomed_camera(camera, zoom)
        w, h = zoomed_size(1920, 1080, zoom)
        assert (zoomed.width_px, zoomed.height_px) == (w, h) and zoomed.focal_px == camera.focal_px
        uv, front = camera.project(points)
        uv_zoomed, front_zoomed = zoomed.project(points)
        np.testing.assert_array_equal(front, front_zoomed)
        # every point lands in the crop where the crop's corner puts it: the same view, a smaller image
        np.testing.assert_allclose(uv_zoomed[front], uv[front] - [(1920 - w) / 2, (1080 - h) / 2], atol=1e-9)
        assert math.isclose(2 * math.degrees(math.atan(w / 2 / zoomed.focal_px)),
                            2 * math.degrees(math.atan(1920 / 2 / zoom / camera.focal_px)), rel_tol=0.01)
    # A principal point given in pixels moves with the crop's corner.
    off_centre = camera.replace(principal_point_px=(950.0, 548.0))
    assert zoomed_camera(off_centre, 2.0).principal_point_px == (950.0 - 480, 548.0 - 270)


def test_the_zoomed_frames_whose_markings_fix_a_camera_are_read_from_the_whole_frames_cameras():
    # A main camera 60 m from the centre spot, 20 m up, aimed at it: twice zoomed it shows the whole centre circle
    # and the halfway line (a circle and a line fix a camera); eight times zoomed, a tenth of the circle and 89 px of
    # the halfway line (nothing that fixes one). Turned 45 deg to the left penalty area: twice zoomed, its lines.
    centre = Camera.from_degrees(focal_px=1500.0, pan_deg=0.0, tilt_deg=70.0, roll_deg=0.0,
                                 position_m=[0.0, 60.0, -20.0], width_px=1280, height_px=720, k1=0.0)
    box = centre.replace(pan_rad=math.radians(-45.0))
    whole = {0: centre, 1: box, 2: None, 3: centre}
    zoomed = {0: zoomed_camera(centre, 2.0), 1: None, 2: None, 3: zoomed_camera(centre, 2.0)}
    assert determinable_figures(whole, zoomed, 2.0) == {
        "reference_frames": 3, "determinable": 3, "determinable_with_camera": 2, "share": 0.6667,
        "first_determinable": 0, "first_camera": 0}
    tight = determinable_figures(whole, {0: None, 1: None, 2: None, 3: zoomed_camera(centre, 8.0)}, 8.0)
    assert tight["determinable"] == 0 and tight["share"] is None and tight["first_camera"] == 3


def test_the_zoomed_runs_cameras_are_compared_with_the_whole_frames_on_the_frames_both_placed():
    whole = Camera.from_degrees(focal_px=2000.0, pan_deg=0.0, tilt_deg=70.0, roll_deg=0.0,
                                position_m=[0.0, 60.0, -20.0], width_px=1280, height_px=720, k1=0.0)
    # one frame the same camera, one 10 % longer and 3-4-0 m off, one the whole run did not place, one neither
    longer = zoomed_camera(whole, 2.0).replace(focal_px=2200.0, position_m=np.array([3.0, 64.0, -20.0]))
    figures = camera_agreement({0: whole, 1: whole, 2: None, 3: whole},
                               {0: zoomed_camera(whole, 2.0), 1: longer, 2: longer, 3: None})
    assert figures["frames"] == 2
    assert figures["focal_ratio_error"]["median"] == 0.05 and figures["position_m"]["median"] == 2.5
    assert math.isclose(figures["focal_ratio_error"]["p95"], 0.095) and math.isclose(figures["position_m"]["p95"], 4.75)
    assert camera_agreement({0: whole}, {0: None}) == {"frames": 0, "focal_ratio_error": {"median": None, "p95": None},
                                                      "position_m": {"median": None, "p95": None}}


def test_the_zoomed_copy_of_a_video_has_every_frame_at_the_crop_size(tmp_path, grey_video):
    video = grey_video(320, 180, 3, 100)
    out = tmp_path / "out" / "grey-zoom2.mp4"
    assert write_copy(video, out, zoom_change(2.0)) == 3
    capture = cv2.VideoCapture(str(out))
    ok, first = capture.read()
    capture.release()
    assert ok and first.shape == (90, 160, 3) and abs(first.mean() - 100) < 8


def test_bench_real_tracks_the_zoomed_copy_and_scores_it_on_the_zoomed_frames(bench_real_video_section):
    section, runs = bench_real_video_section("--zoom", "1.25")
    name = "main-zoom1.25"
    assert section["zoom"] == 1.25 and list(section["clips"]) == [name]
    figures = section["clips"][name]
    assert figures["frames"] == 8 and figures["frames_decoded"] == 8
    # The 640x360 main view's centre at 512x288: the same camera seen through a longer lens, found and aligned on
    # the zoomed frames it was tracked on.
    assert figures["frames_with_camera"] >= 6 and figures["aligned_share_of_camera_frames"] >= 0.8
    # The clip tracked on its whole frames too: the crop of every one of its 8 frames shows markings that fix the
    # camera (the whole view's circle and lines, most of them still in the crop), and the zoomed run placed them.
    assert figures["determinable"]["reference_frames"] == 8 and figures["determinable"]["determinable"] == 8
    assert figures["determinable"]["determinable_with_camera"] == figures["frames_with_camera"]
    assert section["determinable"]["determinable"] == 8 and (runs / "main" / "track.jsonl").is_file()
    # The crop keeps the camera: the two runs' cameras agree (a rendered view wide enough to fix its depth).
    against = figures["against_whole_frames"]
    assert against["frames"] == figures["frames_with_camera"]
    assert against["focal_ratio_error"]["median"] < 0.02 and against["position_m"]["median"] < 1.0
    # The clip, then a cut to its zoomed frames: the zoomed shot placed as the wide shot's camera, on its tripod.
    cut = figures["cut_to_zoom"]
    assert cut["zoomed_frames"] == 8 and cut["with_camera"] >= 6 and cut["same_id_share"] == 1.0
    assert cut["focal_ratio_error"]["median"] < 0.02 and cut["position_m"]["median"] < 1.0
    assert section["cut_to_zoom"]["same_id_share"] == 1.0
    capture = cv2.VideoCapture(str(runs / "copies" / f"{name}.mp4"))
    assert (capture.get(cv2.CAP_PROP_FRAME_WIDTH), capture.get(cv2.CAP_PROP_FRAME_HEIGHT)) == (512, 288)
    capture.release()
    # The runs scored again (--runs): the cut's length and the crop's factor read from its run, the same figures.
    (runs / "copies" / f"{name}-cut.mp4").unlink()
    again, _ = bench_real_video_section("--zoom", "1.25", "--runs", str(runs))
    assert again["clips"][name]["cut_to_zoom"] == cut and not (runs / "copies" / f"{name}-cut.mp4").exists()


def test_bench_real_scores_a_zoomed_and_degraded_copy_on_the_zoomed_frames(bench_real_video_section):
    section, runs = bench_real_video_section("--zoom", "1.25", "--degrade", "400:60:1")
    name = "main-zoom1.25-400px-q60-n1"
    assert list(section["clips"]) == [name] and section["clips"][name]["frames_decoded"] == 8
    for copy, width in ((name, 400), ("main-zoom1.25", 512)):  # tracked on the first, scored on the second
        capture = cv2.VideoCapture(str(runs / "copies" / f"{copy}.mp4"))
        assert capture.get(cv2.CAP_PROP_FRAME_WIDTH) == width
        capture.release()


def test_the_cut_to_the_zoomed_shot_repeats_the_clip_enlarged(tmp_path, read_video):
    # A clip of 3 frames whose left half is dark and right half bright, with a bright square at the centre.
    video = tmp_path / "clip.mp4"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (320, 180))
    image = np.full((180, 320, 3), 40, np.uint8)
    image[:, 160:] = 200
    image[80:100, 150:170] = 255
    for _ in range(3):
        writer.write(image)
    writer.release()
    out = tmp_path / "cut.mp4"
    assert write_zoom_cut(video, out, 2.0) == (3, 2.0)
    assert write_zoom_cut(video, tmp_path / "short.mp4", 2.0, end=2) == (2, 2.0)
    frames = read_video(out)
    assert len(frames) == 6 and all(frame.shape == (180, 320, 3) for frame in frames)
    wide, zoomed = frames[0].astype(float), frames[3].astype(float)
    assert abs(wide[90, 40].mean() - 40) < 10 and abs(zoomed[90, 40].mean() - 40) < 10  # the dark half both times
    # the centre square, 20 px wide, twice as wide in the zoomed shot
    assert wide[90, 135:185].mean(axis=1).max() > 240 and zoomed[90, 125:195].mean() > wide[90, 125:195].mean() + 20
    with pytest.raises(InputError):
        write_zoom_cut(tmp_path / "none.mp4", tmp_path / "bad.mp4", 2.0)


def test_the_zoomed_shot_after_the_cut_is_compared_with_the_wide_shot_on_its_tripod():
    wide = Camera.from_degrees(focal_px=2000.0, pan_deg=0.0, tilt_deg=70.0, roll_deg=0.0,
                               position_m=[0.0, 60.0, -20.0], width_px=1280, height_px=720, k1=0.0)
    tight = wide.replace(focal_px=6000.0)
    off = tight.replace(focal_px=4200.0, position_m=np.array([0.0, 40.0, -14.0]))
    cameras = {0: wide, 1: wide, 2: wide, 3: tight, 4: off, 5: None}
    ids = {0: "main", 1: "main", 2: "main", 3: "main", 4: "main-1", 5: None}
    figures = cut_figures(cameras, ids, 3, 3.0)
    assert figures["wide_id"] == "main" and figures["with_camera"] == 2 and figures["same_id_share"] == 0.5
    assert figures["compared_frames"] == 2 and figures["focal_ratio_error"]["median"] == pytest.approx(0.15)
    assert figures["position_m"]["median"] == pytest.approx(0.5 * np.hypot(20.0, 6.0), abs=0.01)  # rounded to cm
