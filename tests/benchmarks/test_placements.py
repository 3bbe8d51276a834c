"""``bench placements``: a main camera 68 m back and 22 m up (18 deg) is found at a new shot's first frame."""

from __future__ import annotations

import argparse

from broadtrack_graph.benchmarks import placements


def test_a_high_main_camera_is_found_at_its_first_frame_in_every_view():
    parser = argparse.ArgumentParser()
    placements.add_arguments(parser)
    args = parser.parse_args(["--distances", "68", "--elevations", "18", "--reinit-model", "none", "--no-progress"])
    report = placements.run(args)
    rows = report["frames_by_cell"]
    assert [row["view"] for row in rows] == list(placements.VIEWS) and report["frames"] == 3
    assert all(row["height_m"] == 22.1 for row in rows)
    # No field model: the court model places every view at its first frame.
    assert report["found"] == 3, [(row["view"], row["confidence"], row["template_error_px"]) for row in rows]
    assert all(row["template_error_px"] < 1.0 and row["confidence"] > 0.8 for row in rows)
