"""broadtrack-graph: broadcast camera tracking for soccer video as a GTSAM factor graph."""

__version__ = "0.1.0"
