"""Options several suites share."""

from __future__ import annotations


def add_reinit_model(parser, default: str | None = None) -> None:
    """``--reinit-model``: the field model the tracker tries before the global search (``TrackingConfig.reinit_model``;
    default: the tracker's)."""
    from broadtrack_graph.track.config import TrackingConfig

    default = TrackingConfig().reinit_model if default is None else default
    parser.add_argument("--reinit-model", default=default, metavar="shipped|none|FILE",
                        help=f"the learned field model tried before the global search (default {default}; none: no "
                             "model)")


def tracker_options(args) -> dict:
    """The TrackingConfig fields the shared options set: ``reinit_model``."""
    return {"reinit_model": args.reinit_model}

