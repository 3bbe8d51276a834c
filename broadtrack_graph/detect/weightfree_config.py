"""Settings of the weight-free field-marking detector (:class:`~broadtrack_graph.detect.weightfree.WeightFreeDetector`):
every pixel size at one reference working width, whatever the frame's size. No I/O."""

from __future__ import annotations

from dataclasses import dataclass

from broadtrack_graph.detect.faint_lines import FaintLineConfig
from broadtrack_graph.detect.motion_blur import MotionBlurConfig

REFERENCE_WIDTH_PX = 960
"""Working width of the detector; every pixel setting of :class:`WeightFreeConfig` is at this width."""


@dataclass(frozen=True)
class WeightFreeConfig:
    """Settings of :class:`~broadtrack_graph.detect.weightfree.WeightFreeDetector` (pixel sizes at the working width,
    whatever the frame size)."""

    work_width_px: int = REFERENCE_WIDTH_PX  # processing width; the frame is resized (down or up) to it
    grass_hue_min: int = 30  # OpenCV hue (0..180) range of grass
    grass_hue_max: int = 95
    grass_min_saturation: int = 40
    grass_min_value: int = 30
    grass_reach_px: int = 4  # field pixels farther than this from grass are not field (boards, text)
    boundary_margin_px: int = 5  # ridges this close to the field's outer edge are dropped (board bases, stand edges)
    field_min_area_fraction: float = 0.02  # grass regions smaller than this share of the image are ignored
    whole_grass_share: float = 0.9  # a 4x4 cell this much grass or white is whole ...
    field_min_whole_share: float = 0.5  # ... and a field region has at least this share of such cells (0: any)
    marking_channel: str = "luma"  # the image markings are looked for in, "luma" or "min" (ridges.marking_channel)
    presmooth_sigma_px: float = 0.0  # optional Gaussian on the grey image of frames not reduced >= 2x (0 = off)
    tophat_kernel_px: int = 9  # white top-hat size: lines up to about this wide are kept
    tophat_threshold: float = 14.0  # grey levels above the local background (at least) ...
    tophat_noise_margin: float = 4.0  # ... and this much above the 90th percentile of the top-hat on grass
    faint_threshold: float = 8.0  # a blurred frame's pixels above this (and the grass's level) joined to those above
    faint_max_chroma_rise: float = 6.0  # ... and its points more colourful than the ground around by this dropped
    # The faint look (faint straight markings found by their length, detect.faint_lines), offered with the markings
    # found for a frame that needs it (with_faint_lines: the tracker's second look at a lost frame); None: not offered
    faint_lines: FaintLineConfig | None = FaintLineConfig()
    support_window_px: int = 9  # a centre-line point needs min_support others in this window ...
    min_support: int = 7  # ... (a line crossing it gives about the window size; specks fewer)
    orientation_bins: int = 1  # > 2: support counts only neighbours within +-1 of these orientation bins (1: all)
    ridge_sigma_px: float = 1.0  # Gaussian scale of the Hessian
    ridge_min_curvature: float = 1.5  # -lambda_min of the smoothed top-hat (grey levels / px^2)
    side_margin_px: float = 2.0  # a ridge point needs grass this far past its ridge's edges, both sides (0: not)
    # Markings wider than the top-hat's kernel or the Hessian's scale (zoomed views, a low camera's near lines) are
    # found again on the image reduced 2x, 4x (detect.ridges.wide_ridges) when the predicted camera draws a marking
    # at least wide_from_px wide: this many levels; a point whose ridge is flatter than wide_min_peak (curvature
    # across over height, 1 / px^2) is left to the coarser levels, whose top-hat threshold is wide_threshold_factor
    # times the working level's (a wide line is resolved: its paint shows at full contrast) and whose lines rise and
    # fall in steps of at least wide_edge_share of their height (paint, not a mown stripe).
    wide_levels: int = 2
    wide_from_px: float = 7.0
    wide_min_peak: float = 0.06
    wide_threshold_factor: float = 2.0
    wide_edge_share: float = 0.15
    # A blurred frame (its strongest edges this many times a sharp frame's width, detect.sharpness: a fast pan's motion
    # blur, a soft lens) has its wide markings found without a camera, the two gates eased by its blur b (edge share
    # wide_edge_share / b, threshold max(1, wide_threshold_factor / b)): every marking of it is smeared wide and faint.
    blurred_from: float = 1.4
    # A straight motion blur found in the frame (a pan's smear, which leaves the markings along it sharp and the frame
    # reading sharp) is undone on the grey working image before the markings are looked for (detect.motion_blur).
    motion_blur: MotionBlurConfig = MotionBlurConfig()
    player_open_px: int = 5  # opening that removes lines but keeps bodies
    player_min_area_px: int = 40  # smaller non-grass blobs are not players
    # A marking wider than the opening that a player stands on is cut off the blob (detect.player_blobs): the body is
    # its core (this share of its greatest depth D and deeper) grown back by D; pieces beyond longer than
    # player_longest_limb D are cut. A short piece of a far longer blob, no more than twice as deep as what joins it
    # there and well inside the field, is a marking's widest stretch, not a body (detect.player_blobs.marking_pieces).
    player_core_share: float = 0.4
    player_longest_limb: float = 4.0
    player_margin_px: int = 3  # ridge points this close to a player are dropped
    # A box runs on below the body the opening keeps, down its legs to the feet (detect.player_feet): rows holding a
    # pixel this much (grey levels) lighter than the grass around, or not grass, at most this share of its height.
    feet_contrast: float = 25.0
    feet_max_share: float = 1.0
    gate_px: float = 2.0  # naming gate (working pixels) ...
    gate_sigmas: float = 2.5  # ... plus this many predicted uncertainties (frame pixels, scaled to working ones)
    # Named points beyond the pitch's outer lines by more than gate_px + gate_sigmas residual scales of the template
    # registered on the frame's points (and half a marking's width) are dropped (detect.registration).
    register_template: bool = True
    class_consistency_px: float = 1.0  # band (working pixels) around a class's median distance to its prediction
    min_points_per_class: int = 4  # fewer named points: the class is dropped
    point_spacing_px: float = 3.0  # named points are averaged per cell of this size (working pixels)
    # more cells: the class is averaged on coarser cells (solver cost ~ points; fewer bias the tripod)
    max_points_per_class: int = 250
    template_spacing_px: float = 0.5  # densified projected template for naming (working pixels)
    # Named only outside the goals (posts and net are thin white lines too), after markings that can be seen (step 4):
    min_named_width_px: float = 1.4  # at REFERENCE_WIDTH_PX and in a narrower frame's pixels (as the confidence)
    min_named_paint_px: float = 0.25  # working pixels: three quarters of clean paint found (docs/BENCHMARKS.md)
    goal_depth_m: float = 2.5  # the goals' region left out of naming (geometry.goals.goal_region); 0: not left out
    goal_margin_m: float = 0.5
