"""Configuration of the factor graph as frozen dataclasses (units in the names).

Sigmas are in pixels of the observations' resolution, radians, metres; the
per-frame motion sigmas are per frame at the clip's frame rate. ``GraphConfig.from_dict``
rejects unknown keys.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from factors.robust import check_loss
from factors.tripod import DEFAULT_TRIPOD_MODEL


@dataclass(frozen=True)
class MeasurementSigmas:
    """Measurement noise and Cauchy scales (scales in sigmas)."""

    line_sigma_px: float = 1.0  # line/circle point to projected marking distance
    line_cauchy_sigmas: float = 2.5  # scale of the line factor's robust loss (sigmas; the name is the first loss's)
    # The line factor's per-point loss (factors/robust.py): "cauchy" (default) or "geman-mcclure" (redescending: a
    # band of wrongly named points, the boards' ridges named as the far touchline in a blurred sweep, stops pulling;
    # but biased far points stop pulling too). The trade-off measured: docs/BENCHMARKS.md, "Why the defaults".
    line_loss: str = "cauchy"
    keypoint_sigma_px: float = 2.0  # keypoint reprojection at confidence 1
    keypoint_cauchy_sigmas: float = 2.5
    flow_sigma_px: float = 1.0  # flow transfer through the ground plane
    flow_cauchy_sigmas: float = 2.5
    tripod_sigma_m: float = 0.02  # tripod residual sigma (metres)
    # "axis_point" (default): the optical axis passes through T - delta r2 (the full tripod model);
    # "distance": the paper's L_T = delta - |O* - T|, which lets T slide along the optical axis when the
    # pan range is small (docs/BENCHMARKS.md, "Why the defaults").
    tripod_model: str = DEFAULT_TRIPOD_MODEL
    # axis_point with a fixed tripod only: the focal point's place on the optical axis, lambda = r3 . (C - T), stays near
    # its usual value (the entrance pupil moves tens of cm with zoom); None: free. Without it, at
    # tight zoom C slides metres along the axis against f (docs/BENCHMARKS.md, "Why the defaults").
    tripod_lambda_mean_m: float = 0.2
    tripod_lambda_sigma_m: float | None = 0.25
    line_step_m: float = 1.0  # sampling of straight markings for the projected polylines
    arc_step_m: float = 0.25  # sampling of circle arcs

    def __post_init__(self) -> None:
        check_loss(self.line_loss)


@dataclass(frozen=True)
class MotionSigmas:
    """Per-frame random walk and second-difference (smoothness) sigmas."""

    zoom_rel_per_frame: float = 0.01  # sigma of log f_t - log f_{t-1}
    k1_per_frame: float = 0.002
    pan_rad_per_frame: float = math.radians(1.0)
    tilt_rad_per_frame: float = math.radians(0.5)
    roll_rad_per_frame: float = math.radians(0.1)
    position_m_per_frame: float = 0.01  # random walk of the focal point: ~1 cm/frame (it slides along the optical axis with zoom)
    smooth_zoom_rel: float = 0.002  # sigma of the second difference of log f
    smooth_angle_rad: float = math.radians(0.1)  # second difference of pan and tilt
    smooth_roll_rad: float = math.radians(0.02)
    use_smoothness: bool = True  # add the three-frame second-difference factor

    def random_walk_vector(self) -> np.ndarray:
        """(8,) sigmas in state order (log f, k1, pan, tilt, roll, Cx, Cy, Cz)."""
        p = self.position_m_per_frame
        return np.array([
            self.zoom_rel_per_frame, self.k1_per_frame, self.pan_rad_per_frame, self.tilt_rad_per_frame,
            self.roll_rad_per_frame, p, p, p,
        ])

    def smoothness_vector(self) -> np.ndarray:
        """(4,) sigmas for (log f, pan, tilt, roll)."""
        return np.array([self.smooth_zoom_rel, self.smooth_angle_rad, self.smooth_angle_rad, self.smooth_roll_rad])


@dataclass(frozen=True)
class PriorSigmas:
    """Physical ranges and the anchor prior of a frame without a predecessor."""

    focal_min_per_width: float = 0.3  # f_min = 0.3 W (about 118 deg horizontal field of view)
    focal_max_per_width: float = 15.0  # f_max = 15 W (about 3.8 deg)
    focal_edge_sigma_rel: float = 0.02  # softness of the f limits, relative
    k1_min: float = -0.5
    k1_max: float = 0.5
    k1_edge_sigma: float = 0.01
    k1_mean: float = 0.0
    k1_sigma: float = 0.3  # weak Gaussian pull of k1 towards k1_mean
    k1_fixed: bool = False  # hold k1 at its initial value (tight anchor)
    k1_fixed_sigma: float = 1e-6
    anchor_focal_rel: float = 0.5  # anchor of a (re)started frame on its initial guess
    anchor_k1: float = 0.3
    anchor_angle_rad: float = math.radians(10.0)
    anchor_position_m: float = 10.0
    # Online without a tripod, the focal point is held this close (metres) to the camera it starts from when the
    # tracker asks for it (OnlineTracker.hold_position_next: a known, trusted camera restarted after its chain was
    # lost, its place known) and for a re-initialised camera put in the window after its frame's update
    # (OnlineTracker.replace_last: no marking is attached to its state, the camera stands for them). Other restarts
    # keep the wide anchor, so that the frame's markings move a camera found metres off along its line of sight, or
    # reject a wrong one.
    restart_position_m: float = 1.0

    def focal_range_px(self, width_px: int) -> tuple[float, float]:
        return self.focal_min_per_width * width_px, self.focal_max_per_width * width_px

    def anchor_vector(self, state: np.ndarray, position_m: float | None = None) -> np.ndarray:
        """(8,) anchor sigmas around a state (``position_m``: the focal point's instead of ``anchor_position_m``)."""
        a = self.anchor_angle_rad
        p = self.anchor_position_m if position_m is None else position_m
        return np.array([self.anchor_focal_rel * state[0], self.anchor_k1, a, a, a, p, p, p])


@dataclass(frozen=True)
class SolverSettings:
    """iSAM2 / smoother / LM settings."""

    window_frames: int = 20  # frames kept by the online fixed-lag smoother
    # iSAM2 relinearisation thresholds. Relinearising an old frame makes iSAM2 redo the whole
    # window in batch (>65 % of it is affected), so they are loose; a flow-based prediction
    # gives each new frame a good linearisation point instead.
    relinearize_threshold_rad: float = 3e-3  # pan, tilt, roll
    # k1: a projection is linear in k1 itself; k1 changes the other parameters' Jacobians by about 3 dk1 r^2 (r the
    # normalised radius: 0.6 % at 0.2 in an 11 deg view, 5 % at the edge of a 33 deg one). A zoomed view leaves k1
    # free (tenths between frames for well under a pixel in the image): a tighter bar relinearised its window often.
    relinearize_threshold_k1: float = 0.2  # k1
    # f: a projection is linear in f, so a focal length off by df changes only the other parameters' Jacobians, by
    # df / f (under 1 % at 40 px of a 5000 px zoom; 3 % of a wide 1500 px view).
    relinearize_threshold_px: float = 40.0  # f
    relinearize_threshold_m: float = 0.5  # focal point and tripod
    prediction_iterations: int = 1  # Gauss-Newton steps on the flow alone before inserting a frame
    relinearize_skip: int = 1  # iSAM2 checks relinearisation every this many updates
    cache_linearized_factors: bool = True  # iSAM2 option
    extra_iterations_per_frame: int = 1  # extra iSAM2 updates without new factors per frame
    compute_uncertainty: bool = True  # marginal covariances of each finished frame
    lm_max_iterations: int = 50
    lm_relative_tolerance: float = 1e-6
    batch_chunk_frames: int = 1500  # batch LM runs over chunks of at most this many frames
    batch_chunk_overlap_frames: int = 50  # overlap between consecutive chunks
    tripod_prior_T_m: float = 2.0  # weak prior of the tripod variable on its start (batch)
    tripod_delta_prior_m: float | None = 0.2  # prior mean of delta (typical broadcast head); None: no prior
    tripod_delta_prior_sigma_m: float = 0.1  # its sigma; delta is nearly unobservable when the tilt barely changes
    single_frame_cauchy_stages_per_width: tuple[float, ...] = (0.2, 0.04, 0.01)  # graduated Cauchy scales (x W px) before the final one


@dataclass(frozen=True)
class GraphConfig:
    """Everything the graph builder and solvers need (defaults tuned on synthetic tracks)."""

    measurements: MeasurementSigmas = field(default_factory=MeasurementSigmas)
    motion: MotionSigmas = field(default_factory=MotionSigmas)
    priors: PriorSigmas = field(default_factory=PriorSigmas)
    solver: SolverSettings = field(default_factory=SolverSettings)
    use_lines: bool = True
    use_keypoints: bool = True
    use_flow: bool = True
    use_tripod: bool = True  # tripod factor when a tripod is known (or estimated in batch)

    @classmethod
    def from_dict(cls, data: dict) -> "GraphConfig":
        """Build from a nested dict; unknown keys raise ValueError naming them."""
        sections = {f.name: f for f in dataclasses.fields(cls)}
        unknown = set(data) - set(sections)
        if unknown:
            raise ValueError(f"unknown graph config keys: {sorted(unknown)}")
        kwargs = {}
        for name, value in data.items():
            default = getattr(cls(), name)
            if dataclasses.is_dataclass(default):
                sub_fields = {f.name for f in dataclasses.fields(default)}
                bad = set(value) - sub_fields
                if bad:
                    raise ValueError(f"unknown keys in graph config section '{name}': {sorted(bad)}")
                kwargs[name] = dataclasses.replace(default, **value)
            else:
                kwargs[name] = value
        return cls(**kwargs)

    def replace(self, **changes) -> "GraphConfig":
        return dataclasses.replace(self, **changes)
