"""Near misses moved to where the marking map says the camera stands: along its line of sight, or walked."""

from __future__ import annotations

import numpy as np
from reinit_helpers import median_template_error_px as _median_template_error_px

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.mask import fit_points, refine_on_map
from broadtrack_graph.reinit.mask_config import MaskSearchConfig
from broadtrack_graph.reinit.near_miss import along_line_of_sight, fits_here, walk_wide

PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)


def test_a_camera_too_near_with_a_shorter_lens_is_moved_back_along_its_line_of_sight(main_frame):
    from broadtrack_graph.reinit.confidence import camera_confidence

    truth, det = main_frame
    # The trade-off a search can settle in on a real frame: 12 % nearer to the point looked at, f 12 % shorter
    # (the image about that point nearly the same; on this clean frame a fit from there would find its way back).
    C = np.asarray(truth.position_m)
    looked_at = C + (-C[2] / truth.R_cw[2][2]) * truth.R_cw[2]
    near = looked_at + 0.88 * (C - looked_at)
    config = MaskSearchConfig()
    wrong = truth.replace(focal_px=0.88 * truth.focal_px, position_m=tuple(near))
    confidence = lambda camera: camera_confidence(camera, det.marking_mask, CURVES, field_mask=det.field_mask)  # noqa: E731
    assert np.linalg.norm(wrong.position_m - C) > 3.0
    runs = []

    def fits(function, calls, curves, **keywords):  # a runner of the fits (the tracker's spreads them over processes)
        runs.append([args[2] for args in calls])
        return fits_here(function, calls, curves, **keywords)

    moved = along_line_of_sight(wrong, det.marking_points_px, CURVES, config, fits=fits)
    assert len(moved) == 5 and len(runs) == 1 and len(runs[0]) == 5  # one run of the five fits
    for camera, again in zip(moved, along_line_of_sight(wrong, det.marking_points_px, CURVES, config)):
        np.testing.assert_array_equal(camera.to_vector(), again.to_vector())
    best = max(moved, key=confidence)
    assert confidence(best) > confidence(wrong)
    assert np.linalg.norm(best.position_m - C) < 1.0 and _median_template_error_px(best, truth) < 1.0
    # A camera looking above the horizon has no point it looks at: nothing to move.
    assert along_line_of_sight(truth.replace(tilt_rad=np.radians(95.0)), det.marking_points_px, CURVES) == []


def test_a_camera_found_metres_from_where_it_stands_is_walked_there_by_repeated_wide_fits(main_frame):
    truth, det = main_frame
    config = MaskSearchConfig()
    points = fit_points(det.marking_points_px, config)
    # A near miss as a search makes one: fitted at a candidate focal point 4.5 m nearer and 1 m lower, f scaled
    # with the distance to the centre spot (the fit's prior holds it within a few metres of the candidate).
    C = np.asarray(truth.position_m)
    candidate = C + np.array([0.0, -4.5, 1.0])
    start = truth.replace(position_m=tuple(candidate), focal_px=truth.focal_px * np.linalg.norm(candidate)
                          / np.linalg.norm(C))
    near = refine_on_map(start, points, candidate, CURVES, config, config.schedule)
    assert np.linalg.norm(near.position_m - C) > 2.0 and _median_template_error_px(near, truth) > 20.0
    # One wide fit does not get there (its prior, around the near miss, holds it back); walking does.
    once = refine_on_map(near, points, near.position_m, CURVES, config, config.wide_schedule)
    assert _median_template_error_px(once, truth) > 10.0
    walked = walk_wide(near, det.marking_points_px, CURVES, config)
    assert walked is not None
    assert np.linalg.norm(walked.position_m - C) < 0.5 and _median_template_error_px(walked, truth) < 1.0
    # The right camera does not move: nothing to walk.
    assert walk_wide(walked, det.marking_points_px, CURVES, config) is None
