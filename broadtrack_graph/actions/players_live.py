"""Players on the pitch as a tracking run goes (``track --players``): each frame's boxes are located the moment
its record is written.

Every run folder the run writes gets a ``players.jsonl`` beside its ``track.jsonl`` that mirrors it: when
a frame's record is written (camera file, flushed track line), the frame's boxes are located with that
record's camera and marginal standard deviations, exactly as they read back from ``track.jsonl``
(:func:`~broadtrack_graph.actions.players.frame_lines`), and their lines are appended and flushed. An
interrupted run (Ctrl-C, SIGTERM) therefore keeps the players of every frame it wrote.

* Online mode: records are final as written, so ``players.jsonl`` grows with ``track.jsonl``.
* Fixed-lag mode: records are written as they leave the lag window; when the offline recovery gives
  cameras to frames the forward pass lost, the run folder is rewritten, and ``players.jsonl`` with it
  (truncated and rewritten line for line with ``track.jsonl``).
* Batch mode: the online first pass writes ``pass1/track.jsonl`` and the provisional
  ``pass1/players.jsonl``; the refinement writes the run folder's ``track.jsonl`` and ``players.jsonl``
  from the final cameras.

At the end, the game-state predictions and ``players_summary.json`` (and the video on request) are
written from the final folder's lines, in the order of the box frames: the files a run ends with are
those ``broadtrack-graph players RUN --boxes FILE`` writes from the finished run folder.

Box files are read once, before tracking, and indexed by frame id and frame index. A box frame is
matched by its id, else by its index (as :func:`~broadtrack_graph.actions.players.locate_players`);
one whose index was written under another id waits for its own id and, when the id never came, is
located with the record of its index when the pass ends or stops. Box frames the run never wrote
are reported at the end, one line each.

With the detector's own player blobs (``--players detector``) the boxes come from each processed
frame (its detections, or the observations a detections file brought), are linked into tracks as
they come (:class:`~broadtrack_graph.detect.player_ids.TrackIdLinker`, the same ids as linking them
all at the end), and a record written before its frame's blobs waits for them (at most the frame
being processed).
"""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.actions.players import (
    SUMMARY_FILE,
    VIDEO_FILE,
    FrameLines,
    PlayersOptions,
    PlayersResult,
    frame_lines,
    not_in_run_issue,
    write_players_outputs,
)
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.player_boxes import read_player_boxes
from broadtrack_graph.io.players_file import PLAYERS_FILE, PREDICTIONS_FILE, PlayersWriter
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.io.track_record import record_from_json
from broadtrack_graph.types.player_boxes import PlayerBoxes, PlayerFrame
from broadtrack_graph.types.track_record import TrackRecord

log = logging.getLogger(__name__)


class FolderPlayers:
    """The ``players.jsonl`` of one run folder, written as its records are (see the module docstring).

    Args:
        folder: the run folder.
        width_px, height_px: the resolution of its records' cameras (the writer's).
        live: the boxes and options.
    """

    def __init__(self, folder: Path, width_px: int, height_px: int, live: "LivePlayers") -> None:
        self.folder = Path(folder)
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.live = live
        self.writer = PlayersWriter(self.folder / PLAYERS_FILE)
        self.located: dict[int, FrameLines] = {}  # box frame position -> its lines
        self.deferred: dict[int, TrackRecord] = {}  # box frame position -> the record of its index (id not seen yet)
        self.held: list[TrackRecord] = []  # records waiting for their frame's detector blobs

    def record_written(self, record: TrackRecord, line: dict) -> None:
        """Observer of the folder's writer (:data:`~broadtrack_graph.io.track_writer.RecordWritten`)."""
        del record  # the camera as track.jsonl holds it is rebuilt from the line, as reading the run back does
        self.held.append(record_from_json(line, self.width_px, self.height_px))
        self.release()

    def release(self) -> None:
        """Locate the held records whose frames' boxes are all known, in order."""
        while self.held and self.live.boxes_known(self.held[0].frame_index):
            self._locate(self.held.pop(0))

    def _locate(self, record: TrackRecord) -> None:
        live = self.live
        lines = []
        for position in live.matches(record, self.located, self.deferred):
            located = frame_lines(record, live.boxes.frames[position], live.boxes.source, live.options)
            self.located[position] = located
            self.deferred.pop(position, None)
            lines.extend(located.lines)
        self.writer.write_frame(lines)

    def close(self) -> None:
        """The pass is over (or stopped): locate the box frames still waiting for their id with the record of their
        index (their id never came), and close the file."""
        try:
            for position, record in sorted(self.deferred.items()):
                located = frame_lines(record, self.live.boxes.frames[position], self.live.boxes.source,
                                      self.live.options)
                self.located[position] = located
                self.writer.write_frame(located.lines)
            self.deferred.clear()
        finally:
            self.writer.close()

    def result(self) -> PlayersResult:
        """The lines, counts and issues of the closed folder, in the order of the box frames (as
        :func:`~broadtrack_graph.actions.players.locate_players` gives them)."""
        boxes = self.live.boxes
        result = PlayersResult(self.folder, issues=list(boxes.issues))
        for position, frame in enumerate(boxes.frames):
            result.boxes += len(frame)
            if position in self.located:
                result.add(self.located[position])
            else:
                result.issues.append(not_in_run_issue(boxes.source, frame))
        return result


class LivePlayers:
    """Locates a run's players as it writes its records (see the module docstring).

    Args:
        boxes_path: a box file (game-state labels, MOT, detections), or None for the detector's player blobs.
        options: pixel noise, distance limit, analytics, video.

    Use: :meth:`start` once the run's resolution is known (reads the box file: bad input fails before
    tracking), :meth:`observer_for` as the run's record observer, :meth:`frame_done` as its frame observer
    (detector blobs), :meth:`finish` after the run (or :meth:`close` when it stops).
    """

    def __init__(self, boxes_path: str | Path | None, options: PlayersOptions = PlayersOptions()) -> None:
        self.boxes_path = None if boxes_path is None else Path(boxes_path)
        self.options = options
        self.boxes = PlayerBoxes(source="detector", kind="detector")
        self.by_id: dict[str, list[int]] = {}  # frame id -> positions of box frames in self.boxes.frames
        self.by_index: dict[int, list[int]] = {}  # frame index -> positions
        self.linker = None
        self.last_done: int | None = None  # detector blobs: the last frame index processed
        self.current: FolderPlayers | None = None

    @property
    def from_detector(self) -> bool:
        return self.boxes_path is None

    def start(self, width_px: int, height_px: int, out_dir: str | Path) -> None:
        """Read and index the box file at the run's resolution; remove an earlier run's players outputs in out_dir.

        Raises:
            InputError: the box file is missing, unreadable or has no usable box.
        """
        if self.from_detector:
            from broadtrack_graph.detect.player_ids import TrackIdLinker

            self.linker = TrackIdLinker()  # the blobs come without ids: new ids from 0, as link_track_ids gives them
        else:
            boxes = read_player_boxes(self.boxes_path, image_size=(width_px, height_px))
            self.boxes = boxes.scaled(width_px, height_px)
            for position, frame in enumerate(self.boxes.frames):
                self._index(position, frame)
        out = Path(out_dir)
        for name in (PLAYERS_FILE, PREDICTIONS_FILE, SUMMARY_FILE, VIDEO_FILE):
            try:
                (out / name).unlink(missing_ok=True)
            except OSError as exc:
                raise InputError(out / name, f"cannot remove the earlier run's file: {exc.strerror or exc}") from None

    def _index(self, position: int, frame: PlayerFrame) -> None:
        """Index the box frame at this position of ``self.boxes.frames`` by its id and its index."""
        if frame.frame_id is not None:
            self.by_id.setdefault(str(frame.frame_id), []).append(position)
        if frame.frame_index is not None:
            self.by_index.setdefault(int(frame.frame_index), []).append(position)

    # ----------------------------------------------------------------- observers of the run

    def frame_done(self, frame, handed, detections) -> None:
        """Frame observer (:data:`~broadtrack_graph.track.run_context.FrameDone`): collect the detector's blobs."""
        del handed
        if self.from_detector:
            boxes = detections.player_boxes_px if detections is not None else None
            if boxes is None and frame.observations is not None:
                boxes = frame.observations.player_boxes_px
            if boxes is not None and len(boxes):
                self.boxes.add_frame(frame.frame_index, frame.frame_id, boxes)
                self.boxes.frames[-1] = self.linker.link(self.boxes.frames[-1])
                self._index(len(self.boxes.frames) - 1, self.boxes.frames[-1])
            self.last_done = frame.frame_index
            if self.current is not None:
                self.current.release()

    def boxes_known(self, frame_index: int) -> bool:
        """Whether every box of this frame is known (a box file: always; detector blobs: once it was processed)."""
        return not self.from_detector or (self.last_done is not None and frame_index <= self.last_done)

    def observer_for(self, folder: Path, width_px: int, height_px: int):
        """Record observer (:data:`~broadtrack_graph.track.run_context.RecordObserver`): a new ``players.jsonl`` in
        folder."""
        if self.current is not None:  # the previous pass is over: all its frames were processed
            self.current.release()
            self.current.close()
        self.current = FolderPlayers(folder, width_px, height_px, self)
        return self.current.record_written

    def matches(self, record: TrackRecord, located: dict, deferred: dict) -> list[int]:
        """Positions of the box frames a record locates now: by id; else by index when the box frame has no id
        (one with another id is put in ``deferred`` until its id comes or the pass ends)."""
        out = [p for p in self.by_id.get(str(record.frame_id), ()) if p not in located]
        for p in self.by_index.get(int(record.frame_index), ()):
            if p in located or p in out or p in deferred:
                continue
            if self.boxes.frames[p].frame_id is None:
                out.append(p)
            else:
                deferred[p] = record
        return sorted(out)

    # ----------------------------------------------------------------- the end

    def finish(self, run_dir: str | Path, progress: bool = True) -> PlayersResult:
        """After the run: the final folder's lines, predictions and summary (see the module docstring).

        Args:
            run_dir: the folder of the run's final records (``RunResult.out_dir``).
        """
        folder = Path(run_dir)
        if self.current is None or self.current.folder != folder:
            raise RuntimeError(f"no players were located in {folder}")
        self.current.release()
        self.current.close()
        result = self.current.result()
        self.current = None
        write_players_outputs(read_track(folder), self.boxes, result, self.options, str(folder), progress)
        return result

    def close(self) -> None:
        """The run stopped: close the open ``players.jsonl`` (its lines stay; a record still waiting for its frame's
        detector blobs gets none)."""
        if self.current is not None:
            current, self.current = self.current, None
            try:
                current.close()
            except Exception as exc:  # the run's own error is the one to report
                log.warning("%s: %s", current.writer.path, exc)
