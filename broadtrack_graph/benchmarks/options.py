"""Options several suites share."""

from __future__ import annotations

from broadtrack_graph.arguments import int_at_least


def add_reinit_model(parser, default: str | None = None) -> None:
    """``--reinit-model``: the field model the tracker tries before the global search (``TrackingConfig.reinit_model``;
    default: the tracker's)."""
    from broadtrack_graph.track.config import TrackingConfig

    default = TrackingConfig().reinit_model if default is None else default
    parser.add_argument("--reinit-model", default=default, metavar="shipped|none|FILE",
                        help=f"the learned field model tried before the global search (default {default}; none: no "
                             "model)")


def add_search_workers(parser) -> None:
    """``--search-workers``: worker processes running the global search's next stages ahead
    (``TrackingConfig.search_workers``; the cameras are the same with any number)."""
    parser.add_argument("--search-workers", type=int_at_least(0), default=None, metavar="N",
                        help="worker processes running the global search's next stages ahead (default: every core "
                             "but one, at most 3; 0: none, the search in the tracker's process)")


def tracker_options(args) -> dict:
    """The TrackingConfig fields the shared options set: ``reinit_model`` and ``search_workers``."""
    return {"reinit_model": args.reinit_model, "search_workers": getattr(args, "search_workers", None)}

