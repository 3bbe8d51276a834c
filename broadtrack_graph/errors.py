"""Errors the command line reports as one line, naming the file and the problem."""

from __future__ import annotations

from pathlib import Path


class InputError(ValueError):
    """Bad user input: a missing or malformed file, a model of the wrong shape, ...

    The message is one line of the form ``<path>: <problem>`` so that the command
    line can print it as is.
    """

    def __init__(self, path: str | Path | None, problem: str) -> None:
        self.path = None if path is None else Path(path)
        self.problem = " ".join(str(problem).split())  # keep it on one line
        super().__init__(self.problem if path is None else f"{path}: {self.problem}")

    def __reduce__(self):
        # Rebuilt from (path, problem), not from the message (an error raised in another process is re-raised here).
        return type(self), (self.path, self.problem)
