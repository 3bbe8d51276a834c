"""The synthetic detections file: what a detector could report, read back without issues."""

import numpy as np

from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.synth.detections_file import inside_image, write_synthetic_detections
from broadtrack_graph.types.observations import FrameObservations


def test_points_pushed_out_of_the_image_by_the_noise_are_not_written(tmp_path):
    # The main preset's track runs markings off the image border; 1 px noise puts some of their points outside.
    path = write_synthetic_detections(tmp_path / "d.jsonl", 120, seed=5)
    read = read_detections(path)
    assert len(read.frames) == 120
    assert read.issues == []
    assert sum(len(p) for f in read.frames.values() for p in f.lines_px.values()) > 120 * 100


def test_inside_image_keeps_the_pixel_area_and_drops_emptied_classes():
    lines = {"Middle line": np.array([[-0.5, 10.0], [-0.6, 10.0], [99.5, 49.5], [99.6, 20.0]]),
             "Side line top": np.array([[-3.0, 4.0]])}
    kept = inside_image(FrameObservations(0, 100, 50, lines_px=lines))
    assert list(kept.lines_px) == ["Middle line"]
    np.testing.assert_array_equal(kept.lines_px["Middle line"], [[-0.5, 10.0], [99.5, 49.5]])
