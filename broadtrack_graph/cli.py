"""The ``broadtrack-graph`` command line: a thin parser per subcommand.

Each subcommand lives in ``broadtrack_graph/commands/<name>.py`` and exposes
``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int``: it parses
its arguments and calls one action (``broadtrack_graph/actions/``: paths and options in,
files out), which is usable without the command line.

Exit codes (:mod:`broadtrack_graph.commands.console`): 0 done; 2 bad input or bad
arguments (one line on stderr, nothing run); 3 the run finished but produced no camera
at all; 130 interrupted (Ctrl-C or SIGTERM; files written so far are kept and
summary.json says ``"interrupted": true``).
"""

from __future__ import annotations

import os

# Before anything imports cv2: FFmpeg's own log lines (e.g. for a corrupt .mp4) would reach
# stderr ahead of the project's one-line error. The user's own settings win.
os.environ.setdefault("OPENCV_FFMPEG_LOGLEVEL", "-8")  # AV_LOG_QUIET
os.environ.setdefault("OPENCV_LOG_LEVEL", "ERROR")
# Before anything imports numpy: its BLAS on one thread. The court model's products of thousands of small matrices
# split over threads that then wait spinning: on one core they run quicker and take a third less CPU, which the
# process that prepares the frames needs (docs/BENCHMARKS.md, Why the defaults). The processes it starts inherit it.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import importlib  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402

from tqdm.contrib.logging import logging_redirect_tqdm  # noqa: E402

from broadtrack_graph.commands.console import EXIT_INPUT_ERROR, EXIT_INTERRUPTED, setup_logging, teardown_logging  # noqa: E402
from broadtrack_graph.errors import InputError  # noqa: E402

COMMANDS = (
    # one line per subcommand module in broadtrack_graph/commands/
    "evaluate",
    "demo",
    "overlay",
    "compare",
    "track",
    "track-many",
    "bench",
    "calibrate",
    "synth",
    "detect",
    "players",
)


class OneLineParser(argparse.ArgumentParser):
    """argparse with a one-line error (``prog: error: message (see --help)``), exit code 2."""

    def error(self, message: str):
        self.exit(EXIT_INPUT_ERROR, f"{self.prog}: error: {' '.join(message.split())} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="broadtrack-graph",
        description="Broadcast camera tracking for soccer video as a GTSAM factor graph.",
        epilog="exit codes: 0 done, 2 bad input or arguments, 3 the run produced no camera, 130 interrupted",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f"broadtrack_graph.commands.{name.replace('-', '_')}")
        sub = subparsers.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(sub)
        sub.set_defaults(_run=module.run)
    return parser


def _stderr_is_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _sigterm(signum, frame):
    raise KeyboardInterrupt("SIGTERM")


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # a bad argument (one line already printed, code 2) or --help (0)
        return int(exc.code or 0)
    setup_logging(args.verbose)
    if hasattr(args, "no_progress") and not _stderr_is_terminal():
        # A progress bar redraws its line with carriage returns: in a log file every message would share a
        # physical line with a bar. Bars are for terminals; the closing summary line reports the run.
        args.no_progress = True
    previous = signal.getsignal(signal.SIGTERM)
    try:
        signal.signal(signal.SIGTERM, _sigterm)  # a killed run ends like Ctrl-C: summary rewritten
    except ValueError:  # not the main thread (e.g. called from a test runner thread)
        previous = None
    try:
        with logging_redirect_tqdm():
            return int(args._run(args) or 0)
    except InputError as exc:
        print(f"broadtrack-graph {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_INPUT_ERROR
    except KeyboardInterrupt:
        print(f"broadtrack-graph {args.command}: interrupted; files written so far are kept", file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        teardown_logging()
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
