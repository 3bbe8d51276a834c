import math

import numpy as np
import pytest

from broadtrack_graph.geometry.pitch import LINE_CLASSES, MIRRORED_CLASS, Arc, PitchDimensions, PitchTemplate, Segment


def test_26_classes_with_soccernet_geometry():
    pitch = PitchTemplate()
    assert len(LINE_CLASSES) == 26 and set(pitch.elements) == set(LINE_CLASSES)
    side_bottom = pitch.elements["Side line bottom"]
    assert side_bottom.start_w[1] == 34.0 and side_bottom.end_w[1] == 34.0  # near touchline is +y
    assert pitch.elements["Side line top"].start_w[1] == -34.0
    bar = pitch.elements["Goal right crossbar"]
    assert bar.start_w == (52.5, -3.66, -2.44) and bar.end_w == (52.5, 3.66, -2.44)  # z down
    post = pitch.elements["Goal left post left"]
    assert post.start_w == (-52.5, 3.66, -2.44) and post.end_w == (-52.5, 3.66, 0.0)
    main = pitch.elements["Big rect. right main"]
    assert main.start_w == (36.0, -20.16, 0.0) and main.end_w == (36.0, 20.16, 0.0)


def test_penalty_arcs_stay_outside_the_box():
    pitch = PitchTemplate()
    for name, sign in (("Circle left", 1), ("Circle right", -1)):
        arc = pitch.elements[name]
        assert isinstance(arc, Arc)
        points = arc.points_at(np.linspace(0, 1, 50))
        # The arc lies beyond the penalty-area line (|x| <= 36) and its ends touch it.
        assert np.all(np.abs(points[:, 0]) <= 36.0 + 1e-9)
        np.testing.assert_allclose(np.abs(points[[0, -1], 0]), 36.0, atol=1e-9)
        np.testing.assert_allclose(np.hypot(points[:, 0] - sign * -41.5, points[:, 1]), 9.15, atol=1e-9)
        assert arc.length_m == pytest.approx(9.15 * 2 * math.acos(5.5 / 9.15))


def test_soccernet_sampling_counts():
    samples = PitchTemplate().sample_soccernet(0.9, 0.2)
    # Lines: start, int(L / 0.9 - 1) steps of 0.9 m, end.
    assert len(samples["Side line top"]) == int(105 / 0.9 - 1) + 2
    assert len(samples["Goal left post left"]) == int(2.44 / 0.9 - 1) + 2
    np.testing.assert_allclose(samples["Side line top"][1], [-52.5 + 0.9, -34, 0])
    # Centre circle: int(2 pi r / 0.2) points from angle 0, not closed.
    circle = samples["Circle central"]
    assert len(circle) == int(2 * math.pi * 9.15 / 0.2)
    np.testing.assert_allclose(circle[0], [9.15, 0, 0])
    assert np.linalg.norm(circle[-1] - circle[0]) > 0.2
    arc = samples["Circle right"]
    assert len(arc) == int(PitchTemplate().elements["Circle right"].length_m / 0.2) + 2


def test_uniform_sampling_includes_ends_and_spacing():
    samples = PitchTemplate().sample_uniform(step_m=0.5)
    for name, points in samples.items():
        element = PitchTemplate().elements[name]
        spacing = np.linalg.norm(np.diff(points, axis=0), axis=1)
        assert spacing.max() <= 0.5 + 1e-9
        if isinstance(element, Segment):
            np.testing.assert_allclose(points[0], element.start_w)
            np.testing.assert_allclose(points[-1], element.end_w)


def test_keypoints():
    pitch = PitchTemplate()
    kp = pitch.keypoints
    np.testing.assert_allclose(kp["Side line left | Side line top"], [-52.5, -34, 0])
    np.testing.assert_allclose(kp["Middle line | Circle central (top)"], [0, -9.15, 0])
    np.testing.assert_allclose(kp["Big rect. right main | Circle right (bottom)"], [36, math.sqrt(9.15**2 - 5.5**2), 0])
    np.testing.assert_allclose(kp["Right penalty mark"], [41.5, 0, 0])
    np.testing.assert_allclose(kp["Goal right post left (top)"], [52.5, -3.66, -2.44])
    np.testing.assert_allclose(kp["Side line bottom | Middle line"] if "Side line bottom | Middle line" in kp
                               else kp["Middle line | Side line bottom"], [0, 34, 0])
    with pytest.raises(KeyError, match="unknown pitch keypoint"):
        pitch.keypoint_array(["Nowhere"])


def test_dimensions_are_parameters():
    pitch = PitchTemplate(PitchDimensions(length_m=100.0, width_m=64.0))
    np.testing.assert_allclose(pitch.outline_w[2], [50, 32, 0])
    assert pitch.elements["Side line right"].start_w[0] == 50.0
    with pytest.raises(ValueError, match="length_m"):
        PitchDimensions(length_m=-1.0)


def test_mirror_map_is_an_involution_matching_soccernet():
    assert MIRRORED_CLASS["Goal left post left"] == "Goal right post left"
    assert MIRRORED_CLASS["Goal left post right"] == "Goal right post right"
    assert MIRRORED_CLASS["Goal left crossbar"] == "Goal right crossbar"
    assert MIRRORED_CLASS["Big rect. left top"] == "Big rect. right bottom"
    assert MIRRORED_CLASS["Middle line"] == "Middle line" and MIRRORED_CLASS["Circle central"] == "Circle central"
    for name, mirrored in MIRRORED_CLASS.items():
        assert MIRRORED_CLASS[mirrored] == name


@pytest.mark.parametrize("dimensions", [PitchDimensions(), PitchDimensions(length_m=100.0, width_m=64.0)])
def test_mirror_map_matches_the_template_geometry(dimensions):
    """Reflect every class's 3D points through the centre spot: they land on the mirrored class."""
    pitch = PitchTemplate(dimensions)
    samples = pitch.sample_uniform(0.5)
    for name in LINE_CLASSES:
        reflected = samples[name] * np.array([-1.0, -1.0, 1.0])
        distances = {}
        for other in LINE_CLASSES:
            gaps = np.linalg.norm(reflected[:, None, :] - samples[other][None, :, :], axis=2).min(axis=1)
            distances[other] = float(gaps.max())
        landed = min(distances, key=distances.get)
        assert distances[landed] < 0.26, (name, landed, distances[landed])
        assert MIRRORED_CLASS[name] == landed, (name, MIRRORED_CLASS[name], landed)
