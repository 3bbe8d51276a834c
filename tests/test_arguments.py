"""Argument checks at the door: each bad value is one line on stderr naming it and the remedy, exit code 2."""

from __future__ import annotations

import argparse

import pytest

from broadtrack_graph.arguments import (
    finite_float,
    float_between,
    image_side,
    int_at_least,
    positive_float,
    unit_interval,
)
from broadtrack_graph.cli import main


@pytest.mark.parametrize("check, text", [(positive_float, "-5"), (positive_float, "0"), (unit_interval, "7"),
                                         (unit_interval, "-0.1"), (finite_float, "nan"), (finite_float, "inf"),
                                         (int_at_least(1), "0"), (int_at_least(1), "1.5"), (image_side, "8"),
                                         (float_between(0.0, 80.0), "80"), (float_between(0.0, 80.0), "nan")])
def test_bad_values_are_refused(check, text):
    with pytest.raises(argparse.ArgumentTypeError):
        check(text)


def test_good_values_pass():
    assert positive_float("2.5") == 2.5 and unit_interval("0") == 0.0 and unit_interval("1") == 1.0
    assert finite_float("-12") == -12.0 and int_at_least(1)("3") == 3 and image_side("960") == 960


@pytest.mark.parametrize("argv, message", [
    (["evaluate", "--annotations", "a", "--cameras", "c", "--tau", "-5"], "argument --tau: -5 is not positive; give a number > 0"),
    (["track", "clip", "--out", "r", "--confidence-threshold", "7"],
     "argument --confidence-threshold: 7 is outside [0, 1]; give a number between 0 and 1"),
    (["track", "clip", "--out", "r", "--lag", "0"], "argument --lag: 0 is too small; give an integer >= 1"),
    (["track", "clip", "--out", "r", "--reinit-position", "nan", "55", "-12"],
     "argument --reinit-position: 'nan' is not a finite number"),
    (["track", "clip", "--out", "r", "--tripod-position", "0", "55", "-12"],
     "--tripod-position is renamed --reinit-position X Y Z"),
    (["track", "clip", "--out", "r", "--start", "-1"], "argument --start: -1 is too small; give an integer >= 0"),
    (["synth", "--out", "c", "--jpeg-quality", "0"], "argument --jpeg-quality: 0 is out of range; give an integer in [1, 100]"),
])
def test_command_line_refuses_with_one_line(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err


def test_reinit_position_must_be_above_the_pitch(capsys, monkeypatch):
    import broadtrack_graph.commands.track as track_command

    monkeypatch.setattr(track_command, "track_input", lambda *a, **k: pytest.fail("must not run"))
    assert main(["track", "clip", "--out", "r", "--reinit-position", "0", "55", "12"]) == 2
    assert "is not a camera position above the pitch" in capsys.readouterr().err
