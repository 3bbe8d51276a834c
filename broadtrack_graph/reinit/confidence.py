"""Confidence of a camera: agreement of the detected marking map with the projected template.

Compared only where markings can be detected: template samples inside the image, on
the field (not under players when a player mask is given) and wide enough in the
image to be found (a 12 cm line at least ``min_line_width_px`` pixels wide at the working
width and in the frame itself); samples within ``field_edge_px`` of the field's outer edge
are not expected either (the detector looks for no marking there: the bright step of the
boards' bases; a far touchline painted a metre or two from the boards runs in that band).
Both sets live at one reference width (960 px) with a tolerance at that width, so
the measure does not change with the frame resolution:

* recall R: share of the detectable template within ``tolerance_px`` of a detected
  marking pixel (divided by at least ``min_template_px`` samples, so a camera that
  shows almost no template cannot score high). The template too thin to expect joins both
  counts as far as the map shows it anyway: with a share s of it found, weighted
  (s - ``thin_found_share``) / (1 - ``thin_found_share``), nothing at that share or under (a
  wide view from far away, every line under the width, is judged on the lines the detector
  finds there; a camera whose thin lines fall on grass is not helped by them);
* precision P: share of detected marking pixels within ``tolerance_px`` of the template (all of it: a marking
  found on a line too thin to expect, far off, is still explained by it), players (the mask takes their legs:
  light socks and skin are ridges as markings are) and the map's pieces shorter than ``min_piece_length_px`` left
  out (grass texture at a grazing angle leaves specks a few pixels long that no camera explains; a painted line,
  even broken, leaves longer pieces: :func:`~.frame_maps.long_pieces`).

confidence = F-beta(P, R) with beta = 2 (recall weighted: grass texture and clutter
leave specks that no camera explains), scaled down when the camera leaves the playing
surface unexplained: with a field map, the share of its pixels whose rays meet the
ground inside the pitch plus ``field_margin_m`` (:func:`field_coverage`) below
``min_field_coverage`` scales the score by that shortfall. A recall-weighted score
alone can be fooled by a zoomed camera that lays one touchline on the advertising
boards and the rest of its pitch out of view: it explains one line and leaves the
grass in the image off its pitch. Where the camera shows a goal (posts, crossbar and the
net, a box ``goal_depth_m`` deep behind the goal line, ``goal_margin_m`` wider and higher),
neither set counts: a net is a dense mesh of thin white lines that no ground marking explains,
and a camera behind or beside a goal sees much of it. Below ``threshold`` (0.5, BroadTrack) the
tracker re-initialises and ignores flow from the previous camera.

A frame smeared by the camera's motion (the detector's :class:`~broadtrack_graph.detect.motion_blur.MotionBlur`)
leaves a marking that crosses the smear a share ``paint / smear`` of its contrast, where ``paint`` is its painted
width and ``smear`` the blur's length across it (both in pixels): the template where that share is under
``min_smeared_contrast`` is not expected either, and joins the template too thin to expect (counted as far as the map
shows it). The lines along the smear stay sharp and are expected as on any frame. Where the detector keeps the frame's
smeared image (``MotionBlur.image``), a marking across the smear left ``min_checked_smeared_contrast`` or more of its
contrast is asked of that image instead (:func:`~broadtrack_graph.detect.smeared_markings.shown_across_smear`: its
band brighter than the grass beyond both edges, along its length): expected, and found where its band shows, so a
camera is checked across the smear too; a camera that lays those markings on grass loses their recall.

In a fast sweep the tracker also asks :func:`recall_across_motion`: the recall of the template that crosses the
image's motion, the only part that checks a camera along it. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.detect.motion_blur import MotionBlur
from broadtrack_graph.detect.smeared_markings import SmearCheckConfig, shown_across_smear
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.goals import goal_region
from broadtrack_graph.geometry.pixel_neighbours import pixels_within
from broadtrack_graph.geometry.template import TemplateCurves, project_template
from broadtrack_graph.reinit.frame_maps import inside_field_edge, long_pieces

DEFAULT_THRESHOLD = 0.5


@dataclass(frozen=True)
class ConfidenceConfig:
    """Settings of :func:`camera_confidence` (pixels at ``work_width_px``)."""

    work_width_px: int = 960  # comparison width (the weight-free detector's working width)
    tolerance_px: float = 2.5  # a template sample / marking pixel this close to the other set agrees
    template_spacing_px: float = 1.0  # densified template sampling
    min_line_width_px: float = 1.4  # template parts thinner than this (working pixels, and pixels of the frame) are not detectable
    # ... nor those whose painted line is thinner than this across its image (working pixels; geometry.paint_width.
    # painted_widths_px): a line across a grazing line of sight (the far lines of a low camera) is foreshortened to a
    # fraction of its width along it. The weight-free detector finds about half of the paint 0.15-0.2 px wide, more
    # of wider paint, a fifth of thinner (docs/BENCHMARKS.md).
    min_paint_width_px: float = 0.15
    # the template thinner than that is expected in part when over this share of it is found anyway, in whole when
    # all of it is (the detector evidently sees lines that thin in this frame); 1: never
    thin_found_share: float = 0.5
    # a marking across a motion blur left under this share of its contrast (its painted width over the blur's length
    # across it) is not expected (module docstring; 0: every one is)
    min_smeared_contrast: float = 0.075
    # ... and one left this share or more, under min_smeared_contrast, is asked of the smeared image itself where the
    # detector keeps it (MotionBlur.image; detect.smeared_markings): expected, and found where its band shows (1: never)
    min_checked_smeared_contrast: float = 0.03
    smear_check: SmearCheckConfig = SmearCheckConfig()
    min_template_px: int = 150  # recall denominator floor (samples, about pixels of template)
    # the precision reads only the marking map's pieces at least this long (working pixels; frame_maps.long_pieces):
    # specks of grass texture are no camera's markings (0: every piece)
    min_piece_length_px: float = 12.0
    beta: float = 2.0  # F-beta weight of recall over precision
    field_margin_m: float = 10.0  # grass this far outside the lines still counts as explained (run-off, benches)
    min_field_coverage: float = 0.7  # below this share of explained grass the score is scaled by share / this
    field_grid_px: int = 8  # the field map is checked on a grid this coarse (working pixels)
    threshold: float = DEFAULT_THRESHOLD  # below: re-initialise
    goal_depth_m: float = 2.5  # the goals' volume left out of both sets: this deep behind the goal line ...
    goal_margin_m: float = 0.5  # ... and this much wider, higher and in front of it (0 depth: not left out)
    # template samples this close to the field map's outer edge are not compared (0: they are): the weight-free
    # detector keeps no marking there
    field_edge_px: int = WeightFreeConfig.boundary_margin_px


def _resized(mask: np.ndarray, w: int, h: int) -> np.ndarray:
    """The map at (w, h) as bool (the map itself when it is already that: read only)."""
    if mask.shape == (h, w):
        return mask.astype(bool, copy=False)
    return cv2.resize(mask.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0


def confidence_parts(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves | None = None,
                     config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None,
                     player_mask: np.ndarray | None = None, motion_blur: MotionBlur | None = None) -> dict:
    """Precision, recall, their F-beta and the sample counts (see module docstring; ``motion_blur``: the frame's,
    its length in pixels of the marking map's frame, or None)."""
    curves = curves or TemplateCurves()
    compared = compared_sets(camera, marking_mask, curves, config, field_mask, player_mask, motion_blur)
    marks, uv, detectable, field, (w, h) = (compared.marks, compared.uv, compared.detectable, compared.field,
                                            compared.size)
    marking_pixels = int(np.count_nonzero(marks))
    recall = precision = 0.0
    expected = int(np.count_nonzero(detectable))
    if len(uv) and (marking_pixels or compared.shown.any()):
        near, pixel = pixels_within(uv, (w, h), config.tolerance_px)
        found = found_near(marks, near, pixel) | compared.shown
        thin_expected, thin_found = _thin_markings_seen(found, detectable, config)
        recall = float((np.count_nonzero(found & detectable) + thin_found) /
                       max(expected + thin_expected, config.min_template_px))
        # A marking found where the template has a line too thin to expect is still explained by it.
        explained = np.zeros(h * w, bool)
        explained[pixel[near]] = True
        counted = compared.pieces.ravel()
        precision = float(np.count_nonzero(explained & counted) / max(1, np.count_nonzero(counted)))
    b2 = config.beta**2
    score = (1 + b2) * precision * recall / (b2 * precision + recall) if precision + recall > 0 else 0.0
    coverage = 1.0
    if field is not None and score > 0:
        coverage = field_coverage(camera, field, curves.pitch, config.field_margin_m,
                                  config.field_grid_px)
        score *= min(1.0, coverage / config.min_field_coverage) if config.min_field_coverage > 0 else 1.0
    return {"confidence": float(score), "precision": precision, "recall": recall, "field_coverage": coverage,
            "template_samples": expected, "marking_pixels": marking_pixels}


def recall_across_motion(camera: Camera, marking_mask: np.ndarray, motion_px: np.ndarray,
                         curves: TemplateCurves | None = None, config: ConfidenceConfig = ConfidenceConfig(),
                         field_mask: np.ndarray | None = None, player_mask: np.ndarray | None = None,
                         min_angle_deg: float = 45.0) -> tuple[float, int]:
    """The recall of the detectable template that crosses the image's motion: (share found, samples compared).

    A camera moved along the image's motion is checked only by markings that cross it: one laid along the motion
    is explained whatever the error along it. Motion blur smears exactly those crossing markings, so in a fast
    sweep the confidence may stay high while nothing checks the camera along the sweep. The samples compared are
    the detectable ones (module docstring) whose image direction is at least ``min_angle_deg`` from the motion;
    a sample counts as found as for the recall.

    Args:
        camera: the camera to check (any resolution).
        marking_mask: (H, W) bool detected marking map, as for :func:`confidence_parts`.
        motion_px: (2,) the image's motion from the previous frame (any scale: only its direction is used).
        field_mask, player_mask: as for :func:`confidence_parts`.

    Returns:
        (recall in [0, 1], the number of crossing samples); (0, 0) when none crosses or the motion is zero.
    """
    speed = float(np.hypot(*motion_px))
    if speed <= 0:
        return 0.0, 0
    compared = compared_sets(camera, marking_mask, curves or TemplateCurves(), config, field_mask, player_mask)
    uv, detectable = compared.uv, compared.detectable
    if len(uv) < 2:
        return 0.0, 0
    direction, length = _sample_directions(uv, compared.class_index)
    along = np.abs(direction @ (np.asarray(motion_px, float) / speed)) / np.maximum(length, 1e-9)
    crossing = detectable & (length > 0) & (along <= math.cos(math.radians(min_angle_deg)))
    count = int(np.count_nonzero(crossing))
    if count == 0:
        return 0.0, 0
    near, pixel = pixels_within(uv[crossing], compared.size, config.tolerance_px)
    return float(np.count_nonzero(found_near(compared.marks, near, pixel)) / count), count


def _thin_markings_seen(found: np.ndarray, detectable: np.ndarray, config: ConfidenceConfig) -> tuple[float, float]:
    """(samples, of them found) of the template too thin to expect, weighted by how much of it the map shows anyway:
    share s of it found, weight (s - t) / (1 - t) for ``t = thin_found_share`` (0 at t and under: not expected; 1
    when all of it is found: the detector evidently sees lines that thin here)."""
    thin = ~detectable
    total, hit = int(np.count_nonzero(thin)), int(np.count_nonzero(thin & found))
    t = config.thin_found_share
    if hit <= t * total:  # none found, or too little of it (t = 1: never counted)
        return 0.0, 0.0
    weight = (hit / total - t) / (1.0 - t)
    return weight * total, weight * hit


def _sample_directions(uv: np.ndarray, class_index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((N, 2) the image direction of each template sample (N, 2) pixels, towards its neighbours of the same class
    (samples are about 1 px apart), not of unit length; (N,) its length, 0 for a sample with no such neighbour)."""
    same = class_index[1:] == class_index[:-1]
    step = np.where(same[:, None], uv[1:] - uv[:-1], 0.0)
    direction = np.zeros_like(uv)
    direction[:-1] += step
    direction[1:] += step
    return direction, np.linalg.norm(direction, axis=1)


def smeared_contrast(uv: np.ndarray, class_index: np.ndarray, paint_px: np.ndarray, blur: MotionBlur) -> np.ndarray:
    """(N,) the share of its contrast a motion blur leaves each template sample's marking: its painted width over the
    blur's length across the marking's image direction, at most 1 (1 along the smear, and where the direction is
    unknown). Pixels: uv, paint_px and the blur's length at one scale."""
    return _contrast_left(_smear_across(uv, class_index, blur)[0], paint_px)


def _smear_across(uv: np.ndarray, class_index: np.ndarray, blur: MotionBlur) -> tuple[np.ndarray, np.ndarray]:
    """((N,) the blur's length across each template sample's marking (its image direction's), (N, 2) that unit
    direction, zero where unknown). Pixels: uv and the blur's length at one scale."""
    direction, length = _sample_directions(uv, class_index)
    unit = direction / np.maximum(length, 1e-9)[:, None]
    angle = math.radians(blur.angle_deg)
    return blur.length_px * np.abs(unit[:, 0] * math.sin(angle) - unit[:, 1] * math.cos(angle)), unit


def _contrast_left(across_px: np.ndarray, paint_px: np.ndarray) -> np.ndarray:
    """(N,) painted width over the smear's length across, at most 1 (:func:`smeared_contrast`)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(across_px > paint_px, paint_px / across_px, 1.0)


def found_near(marks: np.ndarray, near: np.ndarray, pixel: np.ndarray) -> np.ndarray:
    """(N,) whether each template sample has a marking pixel of ``marks`` (h, w) within the tolerance (``near`` and
    ``pixel`` of :func:`pixels_within`): what the recall counts."""
    return (marks.ravel()[np.where(near, pixel, 0)] & near).any(axis=1)


@dataclass(frozen=True)
class ComparedSets:
    """What a camera is compared with (module docstring), at the working size: the marking map (h, w) bool, the
    template samples kept (N, 2) with their detectable flags, classes and painted widths (working pixels), the field
    map (or None), (w, h); and (N,) the samples across a smear the smeared image shows (found whatever the map)."""

    marks: np.ndarray
    pieces: np.ndarray
    uv: np.ndarray
    detectable: np.ndarray
    class_index: np.ndarray
    paint_px: np.ndarray
    field: np.ndarray | None
    size: tuple[int, int]
    shown: np.ndarray


def compared_sets(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves, config: ConfidenceConfig,
                  field_mask: np.ndarray | None, player_mask: np.ndarray | None,
                  motion_blur: MotionBlur | None = None) -> ComparedSets:
    """The two sets :func:`confidence_parts` compares: on the field, off the players, out of the goals."""
    H, W = marking_mask.shape
    w = config.work_width_px
    h = max(1, int(round(H * w / W)))
    if marking_mask.shape == (h, w):
        marks = marking_mask.astype(bool, copy=False)  # read only
    else:
        # Thin maps must not vanish when reduced: any marking pixel in a cell marks the cell.
        marks = cv2.resize(marking_mask.astype(np.uint8) * 255, (w, h),
                           interpolation=cv2.INTER_AREA if W > w else cv2.INTER_NEAREST) > 0
    whole = marks  # the map before the field, players and goals are taken out of it
    template = project_template(camera, curves, w, h, config.template_spacing_px, paint_widths=True)
    # Detectable: at least min_line_width_px wide at the working width and painted at least min_paint_width_px wide
    # across the line's image, both as wide in the frame itself (upsampling a 640 px frame to the working width does
    # not bring out a line thinner than its pixels).
    enlarged = max(1.0, w / camera.width_px)
    detectable = (template.width_m_px >= config.min_line_width_px * enlarged) & (
        template.paint_width_px >= config.min_paint_width_px * enlarged)
    uv, class_index, paint = template.uv_px, template.class_index, template.paint_width_px
    unsmeared = detectable  # expected but for a smear
    # the blur at these working pixels
    smear = None if motion_blur is None else replace(motion_blur, length_px=motion_blur.length_px * w / camera.width_px)
    if smear is not None and config.min_smeared_contrast > 0 and len(uv):
        detectable = detectable & (smeared_contrast(uv, class_index, paint, smear) >= config.min_smeared_contrast)
    field = None if field_mask is None else _resized(field_mask, w, h)
    players = None if player_mask is None else _resized(player_mask, w, h)
    if len(uv) and (field is not None or players is not None):
        col = np.clip(np.round(uv[:, 0]).astype(int), 0, w - 1)
        row = np.clip(np.round(uv[:, 1]).astype(int), 0, h - 1)
        keep = np.ones(len(uv), bool)
        if field is not None:
            keep &= field[row, col]
            # Not expected in the band along the field's edge; a marking found there is still explained by them.
            edge = inside_field_edge(field, config.field_edge_px)[row, col]
            detectable, unsmeared = detectable & edge, unsmeared & edge
        if players is not None:
            keep &= ~players[row, col]
        uv, detectable, class_index, paint = uv[keep], detectable[keep], class_index[keep], paint[keep]
        unsmeared = unsmeared[keep]
    if field is not None:
        marks = marks & field
    if players is not None:
        marks = marks & ~players  # legs below a body are ridges, not markings
    goals = goal_region(camera, w, h, curves.pitch, config.goal_depth_m, config.goal_margin_m)
    if goals is not None:
        if len(uv):
            outside = ~goals[np.clip(np.round(uv[:, 1]).astype(int), 0, h - 1), np.clip(np.round(uv[:, 0]).astype(int), 0, w - 1)]
            uv, detectable, class_index, paint = uv[outside], detectable[outside], class_index[outside], paint[outside]
            unsmeared = unsmeared[outside]
        marks = marks & ~goals
    shown = np.zeros(len(uv), bool)
    if smear is not None and smear.image is not None and len(uv):
        checked, shown = _checked_across_smear(uv, class_index, paint, unsmeared & ~detectable, smear, (w, h), config)
        detectable = detectable | checked
    return ComparedSets(marks, marks & long_pieces(whole, config.min_piece_length_px), uv, detectable, class_index,
                        paint, field, (w, h), shown)


def _checked_across_smear(uv, class_index, paint, candidates, smear: MotionBlur, size,
                          config: ConfidenceConfig) -> tuple[np.ndarray, np.ndarray]:
    """((N,) the samples asked of the smeared image, (N,) of them those it shows): of ``candidates`` (expected but for
    the smear), those the smear (its length at the working size ``size``) leaves ``min_checked_smeared_contrast`` or
    more (module docstring)."""
    image = smear.image
    to_image = image.channel.shape[1] / size[0]  # the confidence's working pixels -> the smeared image's
    across, unit = _smear_across(uv, class_index, smear)
    asked = candidates & (_contrast_left(across, paint) >= config.min_checked_smeared_contrast)
    checked, shown = np.zeros(len(uv), bool), np.zeros(len(uv), bool)
    if not asked.any():
        return checked, shown
    band = np.maximum(across, paint)
    # a run: consecutive samples of one class about a pixel apart (a piece of one marking in view)
    step = np.linalg.norm(np.diff(uv, axis=0), axis=1)
    run = np.cumsum(np.r_[0, (class_index[1:] != class_index[:-1]) | (step > 3.0 * config.template_spacing_px)])
    index = np.flatnonzero(asked & np.any(unit != 0.0, axis=1))
    normal = np.column_stack([-unit[index, 1], unit[index, 0]])
    on, seen = shown_across_smear(image, uv[index] * to_image, run[index], normal, band[index] * to_image,
                                  config.smear_check)
    checked[index], shown[index] = on, seen
    return checked, shown


def field_coverage(camera: Camera, field_mask: np.ndarray, pitch, margin_m: float = 10.0, grid_px: int = 8) -> float:
    """Share of the playing surface in the image that the camera puts on the pitch.

    Args:
        camera: any resolution.
        field_mask: (h, w) bool map of the playing surface, same aspect ratio as the camera's image.
        pitch: the template (its dimensions).
        margin_m: grass up to this far outside the touch and goal lines counts as on the pitch.
        grid_px: the map is read every grid_px pixels.

    Returns:
        In [0, 1]: the share of field pixels (on the grid) whose rays meet the ground within the lines plus
        margin_m; 1 when the map shows no field.
    """
    h, w = field_mask.shape
    rows, cols = np.mgrid[grid_px // 2:h:grid_px, grid_px // 2:w:grid_px]
    on_field = field_mask[rows, cols]
    if not on_field.any():
        return 1.0
    uv = np.column_stack([cols[on_field], rows[on_field]]).astype(float) * (camera.width_px / w)
    ground, hits = camera.ground_intersection(uv)
    half_length = pitch.dimensions.length_m / 2 + margin_m
    half_width = pitch.dimensions.width_m / 2 + margin_m
    with np.errstate(invalid="ignore"):
        inside = hits & (np.abs(ground[:, 0]) <= half_length) & (np.abs(ground[:, 1]) <= half_width)
    return float(inside.mean())


def camera_confidence(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves | None = None,
                      config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None,
                      player_mask: np.ndarray | None = None, motion_blur: MotionBlur | None = None) -> float:
    """Agreement in [0, 1] of the detected marking map and the camera's projected template.

    Args:
        camera: the camera to check (any resolution).
        marking_mask: (H, W) bool map of detected markings (frame size or a reduced size of the same aspect).
        field_mask, player_mask: optional bool maps (any size of the same aspect); the template only
            counts where the field is visible and no player hides it.
        motion_blur: the frame's motion blur (its length in pixels of the frame ``camera`` is at), or None.

    Returns:
        F-beta of precision and recall (module docstring); 0 when either set is empty.
    """
    return confidence_parts(camera, marking_mask, curves, config, field_mask, player_mask, motion_blur)["confidence"]

