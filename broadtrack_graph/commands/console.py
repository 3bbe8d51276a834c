"""What the command line shows besides results: logging to stderr, counted warnings, the closing summary line.

Warnings and errors go to stderr through the logging module (never ``print``); while a
command runs they are routed through tqdm (``logging_redirect_tqdm``) so that a message
never lands on the progress bar's line. Every warning is counted, and a run's closing
line (:func:`run_summary_line`) reports the count.
"""

from __future__ import annotations

import logging
import sys

log = logging.getLogger(__name__)

from broadtrack_graph.types.status import FrameStatus

EXIT_OK = 0
EXIT_INPUT_ERROR = 2  # bad input: a one-line error, nothing run
EXIT_NO_CAMERA = 3  # the run finished but produced no camera at all
EXIT_INTERRUPTED = 130  # Ctrl-C or SIGTERM: files written so far are kept, summary.json says interrupted


class _Counter(logging.Handler):
    """Counts WARNING-and-above records (it prints nothing)."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.count = 0

    def emit(self, record: logging.LogRecord) -> None:
        self.count += 1


_counter = _Counter()


def setup_logging(verbose: bool = False) -> None:
    """One stderr handler on the root logger (INFO with verbose, else WARNING) and the warning counter."""
    root = logging.getLogger()
    for handler in list(root.handlers):
        if getattr(handler, "_broadtrack", False):
            root.removeHandler(handler)
    stream = logging.StreamHandler(sys.stderr)
    stream.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    stream._broadtrack = True
    root.addHandler(stream)
    if _counter not in root.handlers:
        root.addHandler(_counter)
    root.setLevel(logging.INFO if verbose else logging.WARNING)
    _counter.count = 0


def teardown_logging() -> None:
    """Remove the stderr handler of :func:`setup_logging` (main() calls it on the way out: a caller such as a
    test runner may close that stream later). The warning count stays readable."""
    root = logging.getLogger()
    for handler in list(root.handlers):
        if getattr(handler, "_broadtrack", False) or handler is _counter:
            root.removeHandler(handler)


def warning_count() -> int:
    """Warnings (and errors) logged since :func:`setup_logging`."""
    return _counter.count


def run_summary_line(command: str, summary: dict) -> str:
    """``track: 62 frames, 58 cameras (tracked 50, reinitialised 8, motion-prior 4), 3 warnings``.

    Args:
        summary: a run's summary.json object (``frames_written``, ``status_counts``).
    """
    counts = summary.get("status_counts") or {}
    frames = int(summary.get("frames_written") or 0)
    cameras = sum(int(counts.get(s, 0)) for s in FrameStatus if s.has_camera)
    statuses = ", ".join(f"{name} {count}" for name, count in counts.items() if count)
    marker = " INTERRUPTED" if summary.get("interrupted") else ""
    return (f"{command}:{marker} {frames} frames, {cameras} cameras ({statuses or 'no frame'}), "
            f"{warning_count()} warnings")


def finish_run(command: str, summary: dict) -> int:
    """Print the run's closing line and return its exit code: 3 (logged as an error) when it produced no camera."""
    counts = summary.get("status_counts") or {}
    cameras = sum(int(counts.get(s, 0)) for s in FrameStatus if s.has_camera)
    if cameras == 0:
        log.error("the run produced no camera in %d frames (see the statuses and warnings above); exit code %d",
                  int(summary.get("frames_written") or 0), EXIT_NO_CAMERA)
    print(run_summary_line(command, summary))
    return EXIT_NO_CAMERA if cameras == 0 else EXIT_OK


def print_interrupted_summary(command: str, run_dir) -> None:
    """After Ctrl-C / SIGTERM: the closing line from the run folder's summary.json (rewritten on interrupt)."""
    from broadtrack_graph.errors import InputError
    from broadtrack_graph.io.run_folder import RunFolder

    folder = RunFolder(run_dir)
    for candidate in (folder, folder.pass1()):
        if candidate.has_summary():
            try:
                print(run_summary_line(command, candidate.read_summary()))
                return
            except InputError:
                return
