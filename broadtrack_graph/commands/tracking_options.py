"""Tracking options shared by ``track`` and ``detect``: the flags, and the TrackingConfig they give.

Defaults are :class:`~broadtrack_graph.track.config.TrackingConfig`'s. ``--config FILE``
(TOML, :mod:`broadtrack_graph.io.config_file`) sets any TrackingConfig field, the flow
settings as a ``[flow]`` table; flags given on the command line override the file.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from broadtrack_graph.actions.track import DetectorOptions
from broadtrack_graph.arguments import finite_float, frame_index, int_at_least, unit_interval
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.config_file import read_config_file
from broadtrack_graph.io.tripod_file import read_camera_tripods, read_tripod
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.feed import default_opencv_threads
from broadtrack_graph.types.modes import MODES

_DEFAULT = TrackingConfig()
_DETECTOR = DetectorOptions()


class _Renamed(argparse.Action):
    """``--tripod-position`` was a re-initialisation guess, never a known tripod: it is now ``--reinit-position``."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error("--tripod-position is renamed --reinit-position X Y Z (a re-initialisation guess of the camera "
                     "position, not a known tripod); for a known tripod give --tripod tripod.json")


def add_tracking_arguments(parser) -> None:
    """Options shared by track and detect (config-backed flags default to None: "not given")."""
    parser.add_argument("--config", type=Path, default=None,
                        help="TOML file of tracking options (TrackingConfig fields, [flow] table); flags given here override it")
    parser.add_argument("--mode", choices=MODES, default=None,
                        help=f"online (iSAM2), fixed-lag, or batch (default {_DEFAULT.mode})")
    parser.add_argument("--lag", type=int_at_least(1), default=None,
                        help=f"fixed-lag: frames of future used (default {_DEFAULT.lag_frames})")
    tripod = parser.add_mutually_exclusive_group()
    tripod.add_argument("--tripod", action="append", metavar="[CAMERA_ID=]FILE",
                        help="tripod.json of an earlier run of this camera; repeat as CAMERA_ID=FILE for one tripod per "
                             "camera id of the shots (shots.json; a bare FILE is the main camera's)")
    tripod.add_argument("--reinit-position", type=finite_float, nargs=3, metavar=("X", "Y", "Z"),
                        help="a guess of the camera position in metres (SoccerNet frame, z down, so Z < 0) tried "
                             "when a frame is re-initialised from its markings; not a tripod constraint (for that "
                             "give --tripod FILE). Frames with named lines or keypoints (e.g. a detections file) "
                             "usually re-initialise without it")
    parser.add_argument("--tripod-position", nargs="*", action=_Renamed, help=argparse.SUPPRESS)
    parser.add_argument("--detector", choices=("weightfree", "onnx"), default=_DETECTOR.kind,
                        help=f"field detector (default {_DETECTOR.kind})")
    parser.add_argument("--no-faint-look", dest="faint_look", action="store_false",
                        help="weight-free detector: no second look of the court model at a lost frame's markings "
                             "with the straight paint too faint for the detector's threshold, found along its length")
    parser.add_argument("--segmentation-model", type=Path, help="ONNX line-segmentation model (with its .json contract)")
    parser.add_argument("--keypoint-model", type=Path, help="ONNX keypoint-heatmap model (with its .json contract)")
    parser.add_argument("--field-model", type=Path,
                        help="ONNX field model: keypoint heatmaps and line classes in one (with its .json contract); "
                             "--detector onnx with no model runs the shipped one")
    parser.add_argument("--reinit-model", default=None, metavar="shipped|none|FILE",
                        help="the learned field model tried before the global search when a frame needs a camera "
                             "from nothing: 'shipped' (the package's), 'none', or a field model .onnx with its .json "
                             f"contract (default {_DEFAULT.reinit_model})")
    parser.add_argument("--no-court", action="store_true",
                        help="do not try the court model (a camera from the markings alone, wherever it stands) "
                             "before the field model and the global search")
    parser.add_argument("--no-search", action="store_true",
                        help="on a marking map, do not run the global search (tried last: at a lost camera's own "
                             "position; with --no-court at the known cameras' and the default positions)")
    parser.add_argument("--threads", type=int_at_least(1), default=None, metavar="N",
                        help="OpenCV threads of this process (the cameras are the same with any N; default: the cores "
                             "the tracking and decoding threads leave, at least 1)")
    parser.add_argument("--start", type=frame_index, default=None, help="first frame index (0-based, inclusive)")
    parser.add_argument("--end", type=frame_index, default=None, help="last frame index (exclusive)")
    parser.add_argument("--no-flow", action="store_true", help="switch the optical-flow factor off")
    parser.add_argument("--no-tripod", action="store_true", help="switch the tripod factor off")
    parser.add_argument("--no-k1", action="store_true", help="hold radial distortion k1 at 0")
    parser.add_argument("--confidence-threshold", type=unit_interval, default=None,
                        help=f"re-initialise below this (default {_DEFAULT.confidence_threshold:g})")
    parser.add_argument("--batch-tripod", choices=("fixed", "joint"), default=None,
                        help="batch: hold the first pass's tripod fixed in the refinement or re-estimate it jointly "
                             f"(default {_DEFAULT.batch_tripod})")
    parser.add_argument("--recover-max-frames", type=int, default=None,
                        help="fixed-lag / batch: frames without a camera (before the first lock, in a gap) are recovered "
                             "from their nearest good frame when the gap is at most this long; 0 = off "
                             f"(default {_DEFAULT.recover_max_frames})")


def config_from_args(args) -> TrackingConfig:
    """The TrackingConfig of ``--config`` (or the defaults) with the flags given explicitly on top.

    Raises:
        InputError: a bad config file, or a value TrackingConfig rejects (e.g. ``--lag 0``).
    """
    overrides = {}
    for flag, field in (("mode", "mode"), ("lag", "lag_frames"), ("confidence_threshold", "confidence_threshold"),
                        ("batch_tripod", "batch_tripod"), ("recover_max_frames", "recover_max_frames"),
                        ("reinit_model", "reinit_model")):
        if getattr(args, flag, None) is not None:
            overrides[field] = getattr(args, flag)
    for flag, field in (("no_flow", "use_flow"), ("no_tripod", "use_tripod"), ("no_k1", "estimate_k1"),
                        ("no_court", "court_reinit"), ("no_search", "global_search")):
        if getattr(args, flag, False):
            overrides[field] = False
    if getattr(args, "write_960x540", False):
        overrides["write_960x540"] = True
    return read_config_file(getattr(args, "config", None), TrackingConfig, overrides)


def set_opencv_threads(args) -> int:
    """Set OpenCV's threads for this process from ``--threads`` (default :func:`default_opencv_threads`); returns
    the number set."""
    import cv2

    threads = getattr(args, "threads", None) or default_opencv_threads()
    cv2.setNumThreads(int(threads))
    return int(threads)


def tripods_from_args(args) -> dict[str, Tripod]:
    """The known tripods of ``--tripod [CAMERA_ID=]FILE`` (repeatable) by camera id.

    A bare FILE gives every camera of its ``cameras`` (a run's tripod.json), or its top level as the
    main camera's; CAMERA_ID=FILE gives that camera's entry of the file, or its top level.

    Raises:
        InputError: a camera id given twice, or a tripod file that cannot be read.
    """
    from broadtrack_graph.types.shot import MAIN_CAMERA_ID

    tripods: dict[str, Tripod] = {}
    for value in args.tripod or ():
        camera_id, sep, path = str(value).partition("=")
        if not sep or Path(value).is_file():
            camera_id, path = MAIN_CAMERA_ID, str(value)
        per_camera = read_camera_tripods(Path(path))
        found = per_camera if (not sep or Path(value).is_file()) and per_camera else \
            {camera_id: per_camera.get(camera_id) or read_tripod(Path(path))}
        for key, tripod in found.items():
            if key in tripods:
                raise InputError(Path(path), f"a second tripod for camera '{key}'")
            tripods[key] = tripod
    return tripods


def tripod_from_args(args) -> tuple[Tripod | None, tuple | None]:
    """(known tripod of the main camera (or the first given) from --tripod, re-initialisation position guess
    from --reinit-position).

    Raises:
        InputError: a --reinit-position on or under the pitch (z must be negative: the camera is above it).
    """
    if args.tripod:
        from broadtrack_graph.types.shot import MAIN_CAMERA_ID

        tripods = tripods_from_args(args)
        return tripods.get(MAIN_CAMERA_ID, next(iter(tripods.values()))), None
    if args.reinit_position is not None:
        x, y, z = args.reinit_position
        if z >= 0 or abs(x) > 500 or abs(y) > 500 or z < -200:
            raise InputError(None, f"--reinit-position {x:g} {y:g} {z:g} is not a camera position above the pitch; "
                                   "give metres in the SoccerNet frame with z < 0 (up is negative), e.g. 0 55 -12")
        return None, (x, y, z)
    return None, None


def detector_options(args) -> DetectorOptions:
    field_model = getattr(args, "field_model", None)
    if args.detector == "onnx" and args.segmentation_model is None and args.keypoint_model is None and field_model is None:
        from broadtrack_graph.detect.field_model import SHIPPED_FIELD_MODEL, shipped_field_model

        field_model = shipped_field_model()  # no model given: the shipped one
        if field_model is None:
            raise InputError(SHIPPED_FIELD_MODEL, "--detector onnx without a model needs the shipped field model; "
                                                  "give --segmentation-model / --keypoint-model or --field-model")
    if field_model is not None and (args.segmentation_model is not None or args.keypoint_model is not None):
        raise InputError(field_model, "a field model holds both outputs: give it without --segmentation-model "
                                      "and --keypoint-model")
    if not args.faint_look and args.detector != "weightfree":
        raise InputError(None, "--no-faint-look is the weight-free detector's: give it without --detector onnx")
    return DetectorOptions(args.detector, args.segmentation_model, args.keypoint_model, field_model, args.faint_look)
