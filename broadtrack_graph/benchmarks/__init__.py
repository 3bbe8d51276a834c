"""Benchmark suites behind ``broadtrack-graph bench SUITE``.

Each suite is a module here exposing ``HELP``, ``add_arguments(parser)`` and
``run(args) -> dict`` (the JSON report). Speed and memory targets are measured
here, never asserted in timed unit tests.
"""
