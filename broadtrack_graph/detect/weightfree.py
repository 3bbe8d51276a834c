"""The default, weight-free field-marking detector (no learned model).

Every frame is resized (down or up) to one reference working width (960 px by
default) and all pixel-sized settings are given at that width, so the detector
behaves the same on 960x540, 1073x603, 1280x720 or 1920x1080 input; results are
mapped back to the frame's pixels. Pipeline:

1. grass: HSV thresholds on green; the playing field is the filled outline of the
   large grass regions (so lines and players inside it belong to it) that are mostly
   whole grass (green seats or a green-clad crowd are grassy but speckled: not field;
   :mod:`~broadtrack_graph.detect.playing_field`);
2. players and clutter: non-grass blobs inside the field that survive an opening
   larger than a line's width, with a wider marking a player stands on cut off and a marking's own pieces left out
   (:mod:`~broadtrack_graph.detect.player_blobs`), and look like upright bodies -> boxes and a mask
   (found at half the working width); each box then runs on down its legs to the feet
   (:func:`~broadtrack_graph.detect.player_feet.boxes_to_the_feet`); the player mask returned takes the legs
   too (:func:`~broadtrack_graph.detect.player_feet.with_legs`), but ridges are dropped on the bodies only (a
   marking running under a player's feet, down the image, would be taken for a leg); the legs are found when the
   detections are first read (:class:`~broadtrack_graph.detect.found_markings.FoundMarkings`);
3. marking ridges: white top-hat of the marking channel (:func:`~broadtrack_graph.detect.ridges.marking_channel`: by
   default the grey level), thresholded at a fixed level or, for
   frames not reduced 2x or more to the working width (they keep pixel noise and fine grass
   texture that area averaging removes), above the level the texture reaches on that
   frame (90th percentile on grass plus a margin), inside the field, away from players; each
   candidate pixel is moved to the sub-pixel centre of the ridge with Steger's Hessian method (offset along the
   line normal, kept when within half a pixel), derivatives taken at the candidate pixels only
   (:mod:`~broadtrack_graph.detect.ridges`), and kept with grass on both sides past its edges
   (:mod:`~broadtrack_graph.detect.ridge_sides`); a blurred frame's
   markings, smeared wide and faint, are found on the image reduced 2x and 4x too, with gates eased by its blur
   (:func:`~broadtrack_graph.detect.ridges.wide_ridges`, :mod:`~broadtrack_graph.detect.sharpness`);
4. naming: with a predicted camera, the template is projected and densified
   (:func:`~broadtrack_graph.geometry.template.project_template`); where it draws a marking wider than the
   working level resolves (``wide_from_px``: a zoomed view, a low camera's near lines), the wide markings are found
   first on the reduced levels and the frame's marking map is theirs too; every ridge point takes the class of the
   nearest projected sample (k-d tree) of a marking that can be seen (:func:`~.class_points.seen_markings`) when
   within ``gate_px + gate_sigmas * uncertainty``, except those named
   after a touchline or a goal line that lie beyond the pitch's outline once the template is registered on the named
   points (a turn and a zoom of the prediction: :mod:`~broadtrack_graph.detect.registration`; the boards' edge
   beside a far touchline the frame does not show);
   the points of a class that stay
   (:mod:`~broadtrack_graph.detect.class_points`) are averaged per small grid cell. Without a prediction only the
   unnamed points and the marking map are returned (re-initialisation then works from
   the map: the court model, :func:`broadtrack_graph.reinit.court.reinit_from_court`, and the search of
   :func:`broadtrack_graph.reinit.mask.reinit_from_mask`).

Steps 1-3 need no camera (:meth:`WeightFreeDetector.find_markings`, run by the tracker
ahead of time in the thread that decodes the frames); step 4 is :meth:`~WeightFreeDetector.name`. The faint look
(:meth:`WeightFreeDetector.with_faint_lines`, :mod:`~broadtrack_graph.detect.faint_lines`) adds the straight paint
too faint for step 3, found along its length, to a frame's markings when the tracker asks for it.

Settings: :class:`~broadtrack_graph.detect.weightfree_config.WeightFreeConfig`. No I/O.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import cv2
import numpy as np

from broadtrack_graph.detect.class_points import consistent_classes, seen_markings
from broadtrack_graph.detect.detector import Detections, PredictedCamera, check_image
from broadtrack_graph.detect.faint_lines import with_faint_lines
from broadtrack_graph.detect.found_markings import BodiesToFeet, FaintInputs, FoundMarkings, marked_points
from broadtrack_graph.detect.motion_blur import deblurred, estimate_motion_blur
from broadtrack_graph.detect.player_blobs import bodies_apart_from_markings, upright_bodies
from broadtrack_graph.detect.playing_field import grass_and_field
from broadtrack_graph.detect.point_cells import work_to_frame_px
from broadtrack_graph.detect.registration import named_off_the_pitch
from broadtrack_graph.detect.ridges import WideInputs, marking_channel, marking_ridges, white, wide_points
from broadtrack_graph.detect.sharpness import blur_factor
from broadtrack_graph.detect.smeared_markings import SmearedImage
from broadtrack_graph.detect.weightfree_config import REFERENCE_WIDTH_PX, WeightFreeConfig
from broadtrack_graph.geometry.goals import goal_region
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import ImageTemplate, TemplateCurves, project_template


def presmooth_sigma(frame_width_px: int, work_width_px: int, sigma_px: float) -> float:
    """Extra Gaussian (working pixels) for a frame reduced by frame/work: full at <= 1x, none at >= 2x.

    Area-averaging a frame 2x or more down to the working width already removes pixel noise
    and fine grass texture; a frame near the working width gets the equivalent blur instead.
    """
    ratio = frame_width_px / work_width_px
    return sigma_px * math.sqrt(min(1.0, max(0.0, 4.0 - ratio * ratio) / 3.0))


class WeightFreeDetector:
    """Field markings from colour and shape alone; names them with a predicted camera (module docstring).

    Args:
        pitch: the template used for naming.
        config: thresholds.
    """

    def __init__(self, pitch: PitchTemplate | None = None, config: WeightFreeConfig = WeightFreeConfig()):
        self.pitch = pitch or PitchTemplate()
        self.config = config
        self.curves = TemplateCurves(self.pitch, line_step_m=2.0, circle_step_m=0.5)
        k = config.tophat_kernel_px
        self._tophat_kernel = cv2.getStructuringElement(cv2.MORPH_RECT, (k, k))
        p = max(3, (config.player_open_px // 2) | 1)  # the opening runs at half the working width
        self._open_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (p, p))
        b = 2 * config.boundary_margin_px + 1
        self._boundary_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (b, b))
        m = 2 * config.player_margin_px + 1
        self._margin_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (m, m))
        g = 2 * config.grass_reach_px + 1
        self._reach_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (g, g))
        wide = 2 * config.grass_reach_px * 2 ** config.wide_levels + 1  # a square: the same reach, cheaper
        self._wide_reach_kernel = cv2.getStructuringElement(cv2.MORPH_RECT, (wide, wide))
        # GaussianBlur's kernel for a float image: size round(8 sigma + 1), odd.
        sigma = config.ridge_sigma_px
        self._ridge_kernel = cv2.getGaussianKernel(int(round(sigma * 8 + 1)) | 1, sigma, cv2.CV_32F)

    # ----------------------------------------------------------------- steps

    def field_and_grass(self, small_bgr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(grass, field) uint8 masks (0/255) at the working size (:func:`~broadtrack_graph.detect.playing_field.grass_and_field`)."""
        c = self.config
        return grass_and_field(small_bgr, (c.grass_hue_min, c.grass_hue_max), c.grass_min_saturation, c.grass_min_value,
                               c.whole_grass_share, c.field_min_whole_share, c.field_min_area_fraction)

    def players(self, grass: np.ndarray, field: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(boxes (P, 4) working pixels, mask uint8 at the working size) of upright non-grass blobs in the field.

        The opening and the connected components run at half the working width (bodies are tens of pixels tall there).
        """
        c = self.config
        h, w = grass.shape
        non_grass = cv2.bitwise_and(cv2.bitwise_not(grass), field)
        half = cv2.resize(non_grass, (max(1, w // 2), max(1, h // 2)), interpolation=cv2.INTER_AREA)
        half = cv2.threshold(half, 127, 255, cv2.THRESH_BINARY)[1]
        opened = cv2.morphologyEx(half, cv2.MORPH_OPEN, self._open_kernel)
        opened = bodies_apart_from_markings(opened, c.player_core_share, c.player_longest_limb)
        labels, stats, keep = upright_bodies(opened, half, field, c.player_min_area_px, c.boundary_margin_px)
        x, y, bw, bh = (stats[1:, i] for i in range(4))
        keep_lut = np.concatenate([[False], keep])
        boxes = 2.0 * np.column_stack([x, y, x + bw, y + bh])[keep]
        if not keep.any():
            return np.zeros((0, 4)), np.zeros((h, w), np.uint8)
        mask = cv2.resize(np.take(keep_lut.astype(np.uint8) * 255, labels), (w, h), interpolation=cv2.INTER_NEAREST)
        if c.player_margin_px > 0:
            mask = cv2.dilate(mask, self._margin_kernel)
        return boxes.astype(float).reshape(-1, 4), mask

    def ridges(self, grey: np.ndarray, allowed: np.ndarray, grass: np.ndarray | None = None, blurred: bool = False,
               sides: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points (N, 2) (working pixels), peaked flags (N,), candidate map: :func:`~.ridges.marking_ridges` here."""
        return marking_ridges(grey, allowed, grass, self._tophat_kernel, self._ridge_kernel, self.config, blurred,
                              sides)

    def name_points(self, points_px: np.ndarray, predicted: PredictedCamera, scale: float,
                    size: tuple[int, int], template=None) -> dict[str, np.ndarray]:
        """Class of each working-pixel point from the predicted camera (nearest projected marking within the gate).

        Args:
            points_px: (N, 2) working pixels; scale: working / frame pixels; size: (w, h) working size.
            template: the predicted camera's template at the working size with its paint widths, when projected.
        """
        c = self.config
        w, h = size
        if not len(points_px):
            return {}
        if template is None:
            template = project_template(predicted.camera, self.curves, w, h, c.template_spacing_px, paint_widths=True)
        seen = seen_markings(template.width_m_px, template.paint_width_px, c.min_named_width_px * (
            w / REFERENCE_WIDTH_PX) * max(1.0, REFERENCE_WIDTH_PX / predicted.camera.width_px), c.min_named_paint_px)
        goals = goal_region(predicted.camera, w, h, self.pitch, c.goal_depth_m, c.goal_margin_m)
        if goals is not None and len(points_px):
            points_px = points_px[~goals[np.clip(points_px[:, 1].astype(int), 0, h - 1),
                                         np.clip(points_px[:, 0].astype(int), 0, w - 1)]]
        template_uv, template_class = template.uv_px[seen], template.class_index[seen]
        if not len(template_uv) or not len(points_px):
            return {}
        gate = c.gate_px + c.gate_sigmas * predicted.uncertainty_px * scale
        # Imported here, where it is used: the process that prepares the frames runs find_markings only and starts
        # sooner without scipy (docs/ARCHITECTURE.md). Midpoint splits: built and queried faster than with the
        # default median splits (docs/BENCHMARKS.md).
        from scipy.spatial import cKDTree

        tree = cKDTree(template_uv, balanced_tree=False, compact_nodes=False)
        d, nearest = tree.query(points_px, distance_upper_bound=gate)
        if c.register_template:  # nothing painted lies beyond the pitch's outer lines (detect.registration)
            visible = ImageTemplate(template_uv, template_class, template.width_m_px[seen])
            d[named_off_the_pitch(visible, tree, points_px, d, nearest, gate, predicted.camera.rescaled(w, h),
                                  self.pitch.dimensions, c.template_spacing_px, c.gate_px, c.gate_sigmas)] = np.inf
        ok = np.flatnonzero(np.isfinite(d))
        return consistent_classes(points_px[ok], template_class[nearest[ok]], d[ok], c.class_consistency_px,
                                  c.min_points_per_class, c.point_spacing_px, c.max_points_per_class)

    # ----------------------------------------------------------------- detect

    def area_working_image(self, image_bgr: np.ndarray) -> np.ndarray | None:
        """The colour working image of :meth:`working_images` when it is the frame area-averaged down (a frame at
        least twice the working width; fast at integer ratios), else None. Made once where the frames are decoded
        (``ShotStream``), the shot step's thumbnail is reduced from it too, not from the whole frame."""
        H, W = image_bgr.shape[:2]
        work_w = self.config.work_width_px
        if 2 * work_w > W:
            return None
        return cv2.resize(image_bgr, (work_w, max(1, int(round(H * work_w / W)))), interpolation=cv2.INTER_AREA)

    def working_images(self, image_bgr: np.ndarray, working_bgr: np.ndarray | None = None
                       ) -> tuple[np.ndarray, np.ndarray, float]:
        """(colour, pre-smoothed marking channel) working images and the working / frame pixel scale
        (``working_bgr``: the colour one when already made, :meth:`area_working_image`)."""
        H, W = image_bgr.shape[:2]
        work_w = self.config.work_width_px
        work_h = max(1, int(round(H * work_w / W)))
        scale = work_w / W
        if working_bgr is None or working_bgr.shape[:2] != (work_h, work_w):
            working_bgr = self.area_working_image(image_bgr)
        if working_bgr is not None:
            small = working_bgr
        elif work_w == W:
            small = image_bgr
        else:
            # Bilinear for reductions under 2x (1280 -> 960: area averaging at a non-integer ratio costs about 6x
            # more for a blur of well under a pixel) and for enlargements (640x360 -> 960x540).
            small = cv2.resize(image_bgr, (work_w, work_h), interpolation=cv2.INTER_LINEAR)
        grey = marking_channel(small, self.config.marking_channel)
        sigma = presmooth_sigma(W, work_w, self.config.presmooth_sigma_px)
        if sigma > 0.05:
            grey = cv2.GaussianBlur(grey, (0, 0), sigma)
        return small, grey, scale

    def find_markings(self, image_bgr: np.ndarray, working_bgr: np.ndarray | None = None) -> FoundMarkings:
        """The half of :meth:`detect` that needs no camera: grass, field, players and the marking map.

        The tracker runs it ahead, in the thread that decodes the frames, and names the result
        with :meth:`name` once the camera is predicted; ``detect(image, predicted)`` is
        ``name(find_markings(image), predicted)``. ``working_bgr``: the frame's :meth:`area_working_image` when
        already made (the same numbers). Raises ValueError for an image that is not (H, W, 3) uint8.
        """
        started = time.perf_counter()
        image = check_image(image_bgr)
        H, W = image.shape[:2]
        small, grey, scale = self.working_images(image, working_bgr)
        motion = estimate_motion_blur(grey, self.config.motion_blur)
        smeared = grey
        if motion is not None:  # a pan's smear across the markings, undone first (detect.motion_blur)
            grey = deblurred(grey, motion, self.config.motion_blur.wiener_nsr)
        work_h, work_w = grey.shape
        grass, field = self.field_and_grass(small)
        boxes, player_mask = self.players(grass, field)
        # Markings lie on grass: keep only field pixels with grass close by (drops boards, stands).
        # The outer edge of the field against boards and stands is a bright step, not a marking: keep
        # ridges a margin inside the filled outline (which has no holes at lines or players; the
        # image border is not an edge: erosion pads with the maximum).
        inner = cv2.erode(field, self._boundary_kernel) if self.config.boundary_margin_px > 0 else field
        outline = field
        field = cv2.bitwise_and(field, cv2.dilate(grass, self._reach_kernel))
        pitch = cv2.bitwise_and(field, inner)  # where markings are looked for, and the blur read (the stands are not)
        allowed = cv2.bitwise_and(pitch, cv2.bitwise_not(player_mask))
        # Frames reduced 2x or more to the working width are averaged clean of pixel noise and fine
        # texture: the fixed threshold suits them; others get the threshold adapted to their grass where markings may
        # be (grass-coloured pixels off the field, a green stand or crowd, are not the pitch's texture).
        threshold_grass = cv2.bitwise_and(grass, allowed) if W < 2 * work_w else None
        blur = blur_factor(grey, W, pitch) if self.config.wide_levels > 0 else 1.0
        points, peaked, _ = self.ridges(grey, allowed, threshold_grass, blur >= self.config.blurred_from, grass)
        # What the reduced levels need if the predicted camera draws a wide marking (name): a wide marking's middle
        # lies farther from grass than grass_reach_px. A blurred frame's are found now (then not again).
        wide = WideInputs(grey, cv2.bitwise_and(outline, cv2.bitwise_not(player_mask)), inner, grass, threshold_grass,
                          peaked) if self.config.wide_levels > 0 else None
        if blur >= self.config.blurred_from:  # its faint paint followed (ridges): other sports' coloured lines are not
            points, wide = self._wide_points(wide, points, blur), None
            points = points[white(small, points, self.config.faint_max_chroma_rise)]
        unnamed = Detections(
            width_px=W, height_px=H, motion_blur=motion and replace(
                motion, length_px=motion.length_px / scale, image=SmearedImage(smeared, allowed > 0, scale)),
            **marked_points(points, (work_w, work_h), scale, self.config.point_spacing_px),
            player_boxes_px=(boxes / scale) if len(boxes) else boxes, player_mask=player_mask > 0, field_mask=field > 0,
        )
        # The legs below the bodies are found when the detections are first read (detect.found_markings).
        bodies = BodiesToFeet(boxes, player_mask, grey, grass, self.config.feet_contrast, self.config.feet_max_share,
                              self.config.player_margin_px)
        faint = None if self.config.faint_lines is None else FaintInputs(
            small, allowed, motion is not None or blur >= self.config.blurred_from)
        return FoundMarkings(unnamed, points, (work_w, work_h), scale, time.perf_counter() - started, wide, bodies,
                             faint)

    def with_faint_lines(self, found: FoundMarkings) -> FoundMarkings:
        """``found`` with its faint straight paint added (:func:`~.faint_lines.with_faint_lines`; ``found`` itself when
        it offers no faint look)."""
        return with_faint_lines(found, self._tophat_kernel, self._ridge_kernel, self.config, self.config.faint_lines)

    def name(self, found: FoundMarkings, predicted: PredictedCamera | None = None) -> Detections:
        """The frame's detections: ``found`` with its points named by the predicted camera (none without one).

        When the predicted camera draws a marking at least ``wide_from_px`` wide (working pixels: a zoomed view, a
        low camera's near lines), the wide markings are found first (:func:`~broadtrack_graph.detect.ridges.wide_ridges`)
        and the frame's marking points and map are those."""
        started = time.perf_counter()
        unnamed, points, lines = found.unnamed, found.points_work_px, {}
        if predicted is not None:
            w, h = found.work_size
            template = project_template(predicted.camera, self.curves, w, h, self.config.template_spacing_px,
                                        paint_widths=True)
            if found.wide is not None and len(template.width_m_px) and \
                    template.width_m_px.max() >= self.config.wide_from_px:
                points = self._wide_points(found.wide, points)
                unnamed = replace(unnamed, **marked_points(points, found.work_size, found.scale,
                                                           self.config.point_spacing_px))
            lines = self.name_points(points, predicted, found.scale, found.work_size, template)
        detect_s = found.seconds + time.perf_counter() - started
        return replace(unnamed, lines_px={name: work_to_frame_px(p, found.scale) for name, p in lines.items()},
                       info={"detect_ms": 1000 * detect_s, "work_scale": found.scale})

    def _wide_points(self, wide: WideInputs, points: np.ndarray, blur: float = 1.0) -> np.ndarray:
        """:func:`~broadtrack_graph.detect.ridges.wide_points` with this detector's kernels and settings."""
        return wide_points(wide, points, self._wide_reach_kernel, self._tophat_kernel, self._ridge_kernel, self.config,
                           blur)

    def detect(self, image_bgr: np.ndarray, predicted: PredictedCamera | None = None) -> Detections:
        """Detect field markings in one (H, W, 3) uint8 BGR frame (see module docstring)."""
        return self.name(self.find_markings(image_bgr), predicted)
