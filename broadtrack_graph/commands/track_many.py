"""``broadtrack-graph track-many``: many clips (or whole matches) in parallel on Ray, resumably."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.types.modes import MODES

HELP = "track many clips in parallel units on Ray (local by default, a cluster by --address); resumable"


def add_arguments(parser) -> None:
    parser.add_argument("inputs", nargs="*", type=Path, metavar="INPUT",
                        help="clips: video, frame folder, game-state folder, or a detections file (.jsonl)")
    parser.add_argument("--manifest", type=Path, help="JSON-lines file of clips, one object per line "
                        '({"input"|"detections": PATH, "name", "tripod", "start", "end", "mode", "chunk_frames"})')
    parser.add_argument("--out", required=True, type=Path, help="job folder: one run folder per clip, resumable")
    parser.add_argument("--mode", choices=MODES, default=None,
                        help="mode of clips that set none (default: the --config file's, else online)")
    parser.add_argument("--config", type=Path, default=None, help="TOML file of tracking options (as for track)")
    parser.add_argument("--workers", type=int, default=None, help="local Ray CPUs (default: this machine's cores)")
    parser.add_argument("--address", default=None,
                        help="join a Ray cluster: auto, HOST:PORT (head node) or ray://HOST:PORT (Ray Client)")
    parser.add_argument("--chunk-frames", type=int, default=1500,
                        help="batch mode, detections-file clips: refine in parallel windows of this many frames "
                             "(default 1500)")
    parser.add_argument("--overlap", type=int, default=50, help="frames a window reaches into each neighbour (default 50)")
    parser.add_argument("--retries", type=int, default=2, help="extra attempts of a failing unit (default 2)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    from broadtrack_graph.actions.ray_engine import RayEngine, require_ray
    from broadtrack_graph.actions.track_many import ManyOptions, summary_table, track_many
    from broadtrack_graph.io.config_file import read_config_file
    from broadtrack_graph.io.manifest import clips_from_inputs, read_manifest
    from broadtrack_graph.track.config import TrackingConfig

    require_ray()  # one line on how to install it, before any work
    if bool(args.manifest) == bool(args.inputs):
        raise InputError(None, "give INPUT... or --manifest FILE (one of the two)")
    if args.workers is not None and args.workers < 1:
        raise InputError(None, f"--workers must be >= 1, got {args.workers}")
    if args.chunk_frames < 20 or args.overlap < 0:
        raise InputError(None, "--chunk-frames must be >= 20 and --overlap >= 0")
    clips = read_manifest(args.manifest) if args.manifest else clips_from_inputs(args.inputs)
    config = read_config_file(args.config, TrackingConfig, {"mode": args.mode} if args.mode else {})
    options = ManyOptions(args.chunk_frames, args.overlap, args.retries, not args.no_progress)
    with RayEngine(args.workers, args.address, args.retries) as engine:
        report = track_many(clips, args.out, config, options, engine)
    print(summary_table(report))
    print(f"{len(report.ran)} units run, {len(report.skipped)} already done, {len(report.failed)} failed, "
          f"{len(report.not_run)} not run (inputs failed) in {report.wall_s:.1f} s on {engine.workers} CPUs; "
          f"report: {Path(args.out) / 'track_many.json'}")
    for unit, message in report.failed.items():
        print(f"  failed {unit}: {message}")
    return 1 if report.failed else 0
