"""Options several suites share."""

from __future__ import annotations


def add_reinit_model(parser) -> None:
    """``--reinit-model``: the field model the tracker tries before the global search (``TrackingConfig.reinit_model``)."""
    parser.add_argument("--reinit-model", default="shipped", metavar="shipped|none|FILE",
                        help="the learned field model tried before the global search (default shipped; none: the "
                             "search alone, as before the model)")
