"""The ``broadtrack-graph`` command line: a thin parser per subcommand.

Each subcommand lives in ``broadtrack_graph/commands/<name>.py`` and exposes
``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int``: it parses
its arguments and calls one action (``broadtrack_graph/actions/``: paths and options in,
files out), which is usable without the command line.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys

from broadtrack_graph.errors import InputError

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
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="broadtrack-graph",
        description="Broadcast camera tracking for soccer video as a GTSAM factor graph.",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f"broadtrack_graph.commands.{name.replace('-', '_')}")
        sub = subparsers.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(sub)
        sub.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    try:
        return int(args._run(args) or 0)
    except InputError as exc:
        print(f"broadtrack-graph {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"broadtrack-graph {args.command}: interrupted; files written so far are kept", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
