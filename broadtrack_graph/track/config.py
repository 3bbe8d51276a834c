"""How a clip is tracked: the tracking options (one frozen dataclass; the solver settings they imply are
:mod:`~broadtrack_graph.track.solver_settings`'s). Data only: the process that prepares the frames reads these
options and imports no solver."""

from __future__ import annotations

from dataclasses import dataclass

from broadtrack_graph.detect.flow import FlowConfig
from broadtrack_graph.reinit.confidence import DEFAULT_THRESHOLD
from broadtrack_graph.shots.repeats import RepeatConfig
from broadtrack_graph.types.modes import MODES
from factors.robust import check_loss


@dataclass(frozen=True)
class TrackingConfig:
    """How a clip is tracked (every field can be set from the command line)."""

    mode: str = "online"  # online | fixed-lag | batch (two-pass offline refinement)
    lag_frames: int = 25  # fixed-lag: future frames used before a frame is released
    confidence_threshold: float = DEFAULT_THRESHOLD  # below: re-initialise and distrust flow from this frame
    lost_confidence: float = 0.2  # below this (after a failed re-initialisation): lost, search globally
    # A trusted chain's camera under the threshold is written only while the image moves at most this far a frame
    # (pixels at 960 wide; geometry/tripod.image_motion_px): faster, motion blur smears a marking over many times
    # its width, the markings the confidence reads are lost and the flow nears its reach (docs/METHOD.md).
    max_unsure_motion_px: float = 40.0
    # In such a sweep a camera is written only when the markings crossing the motion are found: at least this share
    # of them (reinit/confidence.recall_across_motion; the others lie along the sweep and do not check it).
    min_recall_across_motion: float = 0.2
    # The one margin of re-initialisation: a camera that is not confident replaces another (the held camera of a
    # trusted chain, a refined guess, an earlier search stage's camera) only when this much more confident.
    reinit_switch_margin: float = 0.1
    cheap_reinit: bool = True  # a lost frame first tries the last confident cameras, refined (False: search at once)
    # The learned field model tried after the court model and before the global search: "none" (the default: on
    # every bench it placed no frame the court model and the search did not; docs/MODEL.md), "shipped" (the
    # package's model), or a field model's .onnx (with its contract)
    reinit_model: str = "none"
    # A camera from the marking map alone, wherever it stands (reinit/court.py), tried after the guesses and before
    # the field model and the global search; taken when its chain can be trusted from it (False: not tried)
    court_reinit: bool = True
    # ... its camera is taken (the field model and the search skipped) only from this confidence, and dropped under
    # it: a camera from nothing that skips the search must be surer than the margin (docs/BENCHMARKS.md, "Why the
    # defaults")
    court_accept_confidence: float = 0.7
    # ... or from this one when the markings it explains hold two straight lines of each direction (they fix the
    # ground plane on their own, a constraint to spare; the cameras wrong at 0.6-0.7 lean on one line across)
    court_grid_accept_confidence: float = 0.6
    # ... or from the margin when the court model's camera of a frame at most this many frames before, in the same
    # stretch, stood in the same place (two frames agreeing; 0: never)
    court_agreement_frames: int = 5
    # ... the two frames' views this far apart at least (the image's motion, geometry.tripod.image_motion_px, as a
    # share of the image width): a still camera's frames show the same markings, and a wrong camera laid on them
    # agrees with itself
    court_agreement_view_change: float = 0.02
    # A new shot's camera this confident is certain: the search stops at it and the field model's camera is taken
    # without a search; below it, both stages are searched.
    certain_confidence: float = 0.9
    # The global search, tried last when the guesses, the court model and the field model give no camera to take: at a
    # lost camera's own position (where the court model does not look, the known cameras' and the default positions
    # too) (False: not tried on a marking map; a detections file's labelled lines, with no map, are searched still)
    global_search: bool = True
    max_guess_age_frames: int = 750  # a confident camera is a guess for this many frames (30 s at 25 fps)
    # The global search's budget: over a stretch where nothing is found it takes about this share of the run
    # (a search stage costs about search_cost_frames tracked frames); each
    # search that finds nothing doubles the wait for the next, up to max_search_backoff times.
    search_time_share: float = 0.2
    search_cost_frames: float = 10.0
    max_search_backoff: int = 8
    use_flow: bool = True  # optical-flow factor between consecutive frames
    detect_shots: bool = True  # video/image input: find cuts (no link across them) and other views (no camera)
    # video/image input: a frame repeating the previous one's image (a frame-rate conversion's duplicate) carries that
    # frame's estimate and is not solved (shots/repeats.py); max_changed_share = 0: every frame is solved
    repeats: RepeatConfig = RepeatConfig()
    mask_graphics: bool = True  # video/image input: mask static broadcast graphics out of detection and flow
    use_tripod: bool = True  # tripod factor (known, fitted online, or estimated in batch)
    estimate_k1: bool = True  # False: k1 held at 0
    line_loss: str = "cauchy"  # the line factor's per-point loss: "cauchy" or "geman-mcclure" (GraphConfig's line_loss)
    tripod_fit_frames: int = 150  # online without a tripod: confident frames tracked before fitting it
    tripod_provisional_frames: int = 25  # ... and before a provisional tripod holds the focal point (0: none)
    tripod_fit_min_confidence: float = 0.6  # only frames at least this confident enter the online tripod fit
    tripod_fit_min_inliers: float = 0.6  # an online fit explaining fewer of its frames is rejected (retried later)
    # batch: "fixed" holds the first pass's tripod (or one fitted to it) in the refinement, where the
    # focal point's place on the axis keeps its prior; "joint" re-estimates T and delta with the track
    # (the height of T and delta trade freely at tight zoom: docs/BENCHMARKS.md, "Why the defaults").
    batch_tripod: str = "fixed"
    # frames without detections in a row that the solver carries on the motion prior (status "motion-prior",
    # no camera written) before the track is dropped and the next detections re-initialise it (25 = 1 s at 25 fps)
    max_motion_prior_frames: int = 25
    min_marking_points: int = 12  # fewer marking points (or too little grass): "no pitch"
    min_grass_share: float = 0.05  # share of the image that must be playing surface
    write_960x540: bool = False  # also write cameras at the calibration benchmark's resolution
    # offline modes: frames the forward pass left without a camera (before the first lock, in a gap)
    # are recovered from their nearest good neighbour when the gap is at most this long (0: off)
    recover_max_frames: int = 250
    flow: FlowConfig = FlowConfig()

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode must be one of {MODES}, got {self.mode!r}")
        if self.court_agreement_frames < 0:
            raise ValueError(f"court_agreement_frames must be >= 0, got {self.court_agreement_frames}")
        if self.court_agreement_view_change < 0:
            raise ValueError(f"court_agreement_view_change must be >= 0, got {self.court_agreement_view_change}")
        if self.lag_frames < 1:
            raise ValueError(f"lag_frames must be >= 1, got {self.lag_frames}")
        if self.recover_max_frames < 0:
            raise ValueError(f"recover_max_frames must be >= 0, got {self.recover_max_frames}")
        if not self.max_unsure_motion_px >= 0.0:
            raise ValueError(f"max_unsure_motion_px must be >= 0, got {self.max_unsure_motion_px}")
        if not 0.0 <= self.min_recall_across_motion <= 1.0:
            raise ValueError(f"min_recall_across_motion must be in [0, 1], got {self.min_recall_across_motion}")
        if not 0.0 <= self.confidence_threshold <= 1.0:
            raise ValueError(f"confidence_threshold must be in [0, 1], got {self.confidence_threshold}")
        if not 0.0 <= self.certain_confidence <= 1.0:
            raise ValueError(f"certain_confidence must be in [0, 1], got {self.certain_confidence}")
        for name in ("court_accept_confidence", "court_grid_accept_confidence"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must be in [0, 1], got {getattr(self, name)}")
        if self.max_motion_prior_frames < 0:
            raise ValueError(f"max_motion_prior_frames must be >= 0, got {self.max_motion_prior_frames}")
        if not 0.0 < self.search_time_share <= 1.0:
            raise ValueError(f"search_time_share must be in (0, 1], got {self.search_time_share}")
        if self.search_cost_frames < 0 or self.max_search_backoff < 1:
            raise ValueError("search_cost_frames must be >= 0 and max_search_backoff >= 1")
        if self.batch_tripod not in ("fixed", "joint"):
            raise ValueError(f"batch_tripod must be 'fixed' or 'joint', got {self.batch_tripod!r}")
        check_loss(self.line_loss)

