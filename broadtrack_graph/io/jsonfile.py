"""JSON helpers: strict reading with one-line errors, atomic writing."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from broadtrack_graph.errors import InputError


def read_text(path: str | Path, what: str = "file") -> str:
    """A text file's content; InputError naming the file when it is missing or unreadable."""
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(path, f"{what} not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read: {exc}") from None


def read_json(path: str | Path):
    """Parse a JSON file; raise InputError naming the file when it is missing, empty or malformed."""
    path = Path(path)
    text = read_text(path)
    if not text.strip():
        raise InputError(path, "empty file")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(path, f"malformed JSON at line {exc.lineno} column {exc.colno}: {exc.msg}") from None


def write_json_atomic(path: str | Path, data, indent: int | None = None) -> None:
    """Write JSON via a temporary file and rename, so a reader never sees half a file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        # One string, then one write: json.dump streams through the pure-Python encoder, json.dumps without an
        # indent runs the C one (the same text, several times faster; a camera file is written every frame).
        text = json.dumps(data, indent=indent, allow_nan=False, default=_json_default)
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; results are for everyone to read
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _json_default(value):
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
