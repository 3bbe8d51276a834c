"""The README's commands cannot drift from the code.

Every ``.venv/bin/broadtrack-graph ...`` line in a ```bash block of README.md must parse
with the real command line; the commands of the tour (between ``<!-- tour -->`` and
``<!-- /tour -->``), which the README says run as written after ``make demo``, are run
in order, as written, in a folder holding a small demo (12 frames at 640x360 instead of
250 at 1920x1080, so the test stays fast).
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from broadtrack_graph.cli import build_parser, main

README = Path(__file__).resolve().parents[1] / "README.md"
PREFIX = ".venv/bin/broadtrack-graph "


def readme_commands(text: str) -> list[list[str]]:
    """Argument lists of the ``.venv/bin/broadtrack-graph`` lines of the ```bash blocks, in order."""
    commands = []
    for block in re.findall(r"```bash\n(.*?)```", text, re.S):
        joined = re.sub(r"\\\n\s*", " ", block)  # continuation lines
        for line in joined.splitlines():
            line = line.strip()
            if line.startswith(PREFIX):
                commands.append(shlex.split(line[len(PREFIX):], comments=True))
    return commands


def tour_text(text: str) -> str:
    match = re.search(r"<!-- tour -->(.*?)<!-- /tour -->", text, re.S)
    assert match, "README.md has no <!-- tour --> ... <!-- /tour --> section"
    return match.group(1)


def test_readme_commands_are_found():
    text = README.read_text()
    assert len(readme_commands(text)) >= 10
    assert len(readme_commands(tour_text(text))) >= 5
    assert readme_commands("```bash\n.venv/bin/broadtrack-graph evaluate --a x \\\n    --b y  # note\n```\n") == [
        ["evaluate", "--a", "x", "--b", "y"]]


@pytest.mark.parametrize("argv", readme_commands(README.read_text()), ids=lambda argv: " ".join(argv)[:60])
def test_every_readme_command_parses(argv):
    build_parser().parse_args(argv)


def test_the_tour_runs_as_written_after_the_demo(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["demo", "--out", "runs/demo", "--frames", "12", "--width", "640", "--height", "360",
                 "--no-overlay", "--no-progress"]) == 0
    for argv in readme_commands(tour_text(README.read_text())):
        argv = argv + (["--no-progress"] if _takes_no_progress(argv) else [])
        code = main(argv)
        assert code == 0, f"README tour command failed ({code}): broadtrack-graph {' '.join(argv)}\n{capsys.readouterr().err}"


def _takes_no_progress(argv: list[str]) -> bool:
    """Progress bars off in the test when the command has the option (the README leaves them on)."""
    parser = build_parser()
    try:
        parser.parse_args(argv + ["--no-progress"])
    except SystemExit:
        return False
    return "--no-progress" not in argv
