"""The README's and docs' commands and links cannot drift from the code.

Every ``.venv/bin/broadtrack-graph ...`` command in a ```bash block of README.md or docs/*.md
must parse with the real command line, and must be either

* in the tour (between ``<!-- tour -->`` and ``<!-- /tour -->``, in one of those files): the
  tour is run in order, as written, in a folder holding a small demo (12 frames at 640x360
  instead of 250 at 1920x1080, so the test stays fast); or
* marked by a trailing comment that starts with one of :data:`MARKERS`: ``# needs your data``
  (it reads data the user brings: a video, SoccerNet files, ...) or ``# long: a benchmark``
  (it needs nothing but time). Marked commands are only parsed.

A command may span lines with a trailing backslash; its marker goes at the end of its last
line. Commands outside ```bash blocks are not checked, so ``broadtrack-graph`` command lines
anywhere else in a code block are an error. Every relative link and image must point to an
existing file, and an anchor ``FILE.md#anchor`` to a heading of that file.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest

from broadtrack_graph.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOC_FILES = (README, *sorted((ROOT / "docs").glob("*.md")))
PREFIX = ".venv/bin/broadtrack-graph "
MARKERS = ("needs your data", "long: a benchmark")
"""Trailing comments that mark a command the test parses but does not run."""
README_MAX_LINES = 150
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.S | re.M)
TOUR = re.compile(r"<!-- tour -->(.*?)<!-- /tour -->", re.S)


@dataclass(frozen=True)
class Command:
    """One ``.venv/bin/broadtrack-graph`` command of a ```bash block."""

    source: str  # "README.md:42" (file and line of the command's first line)
    argv: tuple[str, ...]  # the arguments after the program name
    comment: str  # the trailing comment without "#", or ""
    offset: int  # character offset of the command in its file (to tell whether it is in the tour)

    @property
    def marked(self) -> bool:
        return self.comment.startswith(MARKERS)


def split_comment(line: str) -> tuple[str, str]:
    """(code, comment) of a shell line: the comment starts at a ``#`` outside quotes that begins a word."""
    quote = None
    for i, char in enumerate(line):
        if quote:
            if char == quote:
                quote = None
        elif char in "'\"":
            quote = char
        elif char == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i], line[i + 1:].strip()
    return line, ""


def bash_commands(text: str, name: str = "<text>") -> list[Command]:
    """The ``.venv/bin/broadtrack-graph`` commands of the ```bash blocks of ``text``, in order."""
    commands = []
    for block in FENCE.finditer(text):
        if block.group(1).strip() != "bash":
            continue
        offset = block.start(2)
        pending, start = "", None
        for raw in block.group(2).splitlines(keepends=True):
            line = raw.rstrip("\n")
            if start is None:
                start = offset
            code, comment = split_comment(line)
            if not comment and code.rstrip().endswith("\\"):
                pending += code.rstrip()[:-1] + " "
            else:
                joined = (pending + code).strip()
                if joined.startswith(PREFIX):
                    line_number = text.count("\n", 0, start) + 1
                    commands.append(Command(f"{name}:{line_number}", tuple(shlex.split(joined[len(PREFIX):])),
                                            comment, start))
                pending, start = "", None
            offset += len(raw)
    return commands


def tour_span() -> tuple[Path, int, int]:
    """(file, start, end) of the one tour among README.md and docs/*.md."""
    found = [(path, match.start(1), match.end(1)) for path in DOC_FILES for match in TOUR.finditer(path.read_text())]
    assert len(found) == 1, f"expected one <!-- tour --> ... <!-- /tour --> section, found {len(found)}"
    return found[0]


def tour_commands() -> list[Command]:
    path, start, end = tour_span()
    return [c for c in bash_commands(path.read_text(), str(path.relative_to(ROOT))) if start <= c.offset < end]


def all_commands() -> list[tuple[Path, Command]]:
    return [(path, command) for path in DOC_FILES
            for command in bash_commands(path.read_text(), str(path.relative_to(ROOT)))]


def test_commands_are_found():
    assert len(all_commands()) >= 30
    assert len(tour_commands()) >= 5
    text = ("```bash\n.venv/bin/broadtrack-graph evaluate --a x \\\n    --b 'y # z'  # needs your data: a note\n"
            "# a comment\nmake demo\n.venv/bin/broadtrack-graph track in --out o\n```\n"
            "```text\n.venv/bin/broadtrack-graph not bash\n```\n")
    first, second = bash_commands(text)
    assert (first.argv, first.comment, first.marked) == (("evaluate", "--a", "x", "--b", "y # z"),
                                                         "needs your data: a note", True)
    assert (second.argv, second.comment, second.marked, second.source) == (("track", "in", "--out", "o"), "",
                                                                           False, "<text>:6")


@pytest.mark.parametrize("command", [c for _, c in all_commands()], ids=lambda c: c.source)
def test_every_command_parses(command):
    build_parser().parse_args(list(command.argv))


def test_every_command_is_run_or_marked():
    tour = {c.source for c in tour_commands()}
    unmarked = [f"{c.source}: broadtrack-graph {' '.join(c.argv)}" for _, c in all_commands()
                if c.source not in tour and not c.marked]
    assert not unmarked, ("commands neither in the tour nor marked with a trailing comment starting with "
                          f"{' or '.join(repr('# ' + m) for m in MARKERS)}:\n" + "\n".join(unmarked))
    marked_in_tour = [c.source for c in tour_commands() if c.marked]
    assert not marked_in_tour, f"tour commands are run; they need no marker: {marked_in_tour}"


def test_no_command_escapes_the_checks():
    """A command line in a non-bash block, or without the .venv/bin prefix, would not be parsed: not allowed."""
    bad = []
    for path in DOC_FILES:
        text = path.read_text()
        for block in FENCE.finditer(text):
            kind = block.group(1).strip()
            for line in block.group(2).splitlines():
                code = line.strip()
                if (kind != "bash" and code.startswith(PREFIX)) or code.startswith("broadtrack-graph "):
                    bad.append(f"{path.relative_to(ROOT)}: ```{kind}: {code[:70]}")
        outside = FENCE.sub("", text)
        bad += [f"{path.relative_to(ROOT)}: indented: {line.strip()[:70]}" for line in outside.splitlines()
                if re.match(r"^( {4,}|\t)(\.venv/bin/)?broadtrack-graph ", line)]
    assert not bad, "command lines the test cannot check (use a ```bash block and .venv/bin/):\n" + "\n".join(bad)


def test_the_tour_runs_as_written_after_the_demo(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["demo", "--out", "runs/demo", "--frames", "12", "--width", "640", "--height", "360",
                 "--no-overlay", "--no-progress"]) == 0
    for command in tour_commands():
        argv = list(command.argv)
        argv += ["--no-progress"] if _takes_no_progress(argv) else []
        code = main(argv)
        assert code == 0, (f"tour command failed ({code}) at {command.source}: broadtrack-graph {' '.join(argv)}\n"
                           f"{capsys.readouterr().err}")


def _takes_no_progress(argv: list[str]) -> bool:
    """Progress bars off in the test when the command has the option (the docs leave them on)."""
    parser = build_parser()
    try:
        parser.parse_args(argv + ["--no-progress"])
    except SystemExit:
        return False
    return "--no-progress" not in argv


# ----------------------------------------------------------------------------------------- links


def heading_anchors(text: str) -> set[str]:
    """GitHub's anchors of the markdown headings of ``text`` (code blocks left out)."""
    anchors, seen = set(), {}
    for line in FENCE.sub("", text).splitlines():
        match = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not match:
            continue
        slug = re.sub(r"[^\w\- ]", "", match.group(1).lower()).replace(" ", "-")
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        anchors.add(slug if count == 0 else f"{slug}-{count}")
    return anchors


def relative_links(text: str) -> list[str]:
    """Targets of the markdown links and images of ``text`` that are not URLs (code left out)."""
    prose = re.sub(r"`[^`\n]*`", "", FENCE.sub("", text))
    targets = re.findall(r"!?\[[^\]\n]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)", prose)
    targets += re.findall(r"^\s*\[[^\]\n]+\]:\s*(\S+)", prose, re.M)  # reference definitions
    return [t for t in targets if not re.match(r"^[a-z][a-z0-9+.-]*:", t, re.I)]


def test_relative_links_point_to_existing_files():
    assert heading_anchors("# A `b`: c.d (e)\n```bash\n# not a heading\n```\n## A `b`: c.d (e)\n") == {
        "a-b-cd-e", "a-b-cd-e-1"}
    assert relative_links("see [x](docs/A.md#b), ![i](img.png), `[c](code.md)`, [u](https://x.y)") == [
        "docs/A.md#b", "img.png"]
    broken = []
    for path in DOC_FILES:
        links = relative_links(path.read_text())
        for target in links:
            file_part, _, anchor = target.partition("#")
            linked = (path.parent / file_part).resolve() if file_part else path
            if not linked.exists():
                broken.append(f"{path.relative_to(ROOT)}: {target}: no such file")
            elif anchor and linked.suffix == ".md" and anchor not in heading_anchors(linked.read_text()):
                broken.append(f"{path.relative_to(ROOT)}: {target}: no heading with that anchor")
    assert not broken, "broken links:\n" + "\n".join(broken)
    assert len([t for p in DOC_FILES for t in relative_links(p.read_text())]) >= 20


def test_readme_is_short_and_starts_with_the_two_commands():
    lines = README.read_text().splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines, at most {README_MAX_LINES}"
    first_screen = "\n".join(lines[:30])
    assert "make demo" in first_screen and "make test" in first_screen
