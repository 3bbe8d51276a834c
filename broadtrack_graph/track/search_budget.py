"""The re-initialisation's budgets in frames: how often the global search, the field model and the guesses of every
known camera run where nothing is found.

Counted in frames, not seconds, so a run gives the same cameras on any machine; the re-initialisation
policy (:mod:`broadtrack_graph.track.reinit_policy`) asks them before each search and each try of the
field model or of the known cameras' guesses at a shot's start (:class:`TrySchedule`, one each).

The rules (searches of the marking map; keypoints and labelled lines are searched at once, in
milliseconds):

* a known camera lost mid-shot (a blurred sweep) is still there: it is searched again after
  1, 2, 4, ... frames (at most ``8 * max_search_backoff`` apart), a stage or two each (so is a shot's
  provisional camera, found above the threshold but not yet trusted: until a search finds one
  trusted from its frame, the gaps grow);
* a shot whose camera is not known is searched at its first frame (the shot's own search, which leaves
  the bucket empty), then paid from a bucket that fills by one stage every ``search_cost_frames * (1 - s) / s``
  frames (s = ``search_time_share``; a stage costs about ``search_cost_frames`` tracked frames), holding
  at most one, each stage paid (the bucket goes into debt): over any stretch after the shot's first search where nothing is
  found, searching takes about the share s of the run. Each search that finds nothing
  confident doubles the price of the next (up to ``max_search_backoff``), so the gaps grow: a shot whose first
  frame could not be placed is searched again a few seconds later, on frames that may show more.

A cut or a view change (:meth:`~broadtrack_graph.track.reinit_policy.ReinitPolicy.new_stretch`) and a
confident frame (:meth:`~broadtrack_graph.track.reinit_policy.ReinitPolicy.confident`) restart the budget.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class SearchBudget:
    """The global search's budget in frames (module docstring).

    refill_frames: frames that pay for one search stage (a shot whose camera is not known).
    max_backoff: the price of a search doubles after each that finds nothing, up to this many searches;
        a known camera lost mid-shot is searched again after 1, 2, 4, ... frames, up to this many times
        ``max_gap_frames``.
    """

    refill_frames: float
    max_backoff: int = 8
    tokens: float = 1.0
    price: float = 1.0
    max_gap_frames: int = 8
    _last_frame: int | None = None
    _gap: int = 1
    _next_known: int | None = None

    def _refill(self, frame_index: int) -> None:
        if self.refill_frames <= 0:  # no budget: every search is paid for
            self.tokens = self.price
        elif self._last_frame is not None and frame_index > self._last_frame:
            self.tokens = min(self.price, self.tokens + (frame_index - self._last_frame) / self.refill_frames)
        self._last_frame = frame_index

    def allows(self, frame_index: int, known_camera: bool = False) -> bool:
        """A search may run at this frame (known_camera: the shot's camera is known, lost mid-shot)."""
        self._refill(frame_index)
        if known_camera:
            return self.refill_frames <= 0 or self._next_known is None or frame_index >= self._next_known
        return self.tokens >= self.price - 1e-9

    def next_frame(self, frame_index: int, known_camera: bool = False) -> int:
        """The first frame at which a search will be allowed (from frame_index on)."""
        self._refill(frame_index)
        if known_camera:
            return max(frame_index, self._next_known if self._next_known is not None else frame_index)
        return frame_index + max(0, int(np.ceil((self.price - self.tokens) * self.refill_frames - 1e-9)))

    def spend(self, frame_index: int, found: bool, searches: int = 1, known_camera: bool = False,
              shot_start: bool = False) -> None:
        """A search of ``searches`` stages ran at frame_index; found: it gave a confident camera; shot_start: the search
        at a shot's start (the shot's own: the bucket is left empty, not in debt)."""
        if known_camera:
            # The camera is still there, only lost: searched again soon, then less and less often.
            self._next_known = None if found else frame_index + self._gap
            self._gap = 1 if found else min(2 * self._gap, self.max_gap_frames * self.max_backoff)
            return
        self.tokens = 0.0 if shot_start else self.tokens - self.price * max(1, searches)
        self.price = 1.0 if found else min(self.price * 2.0, float(self.max_backoff))

    def restart(self) -> None:
        """A new stretch (a cut, a view change, a confident frame): the next search is paid at once."""
        self.tokens, self.price, self._gap, self._next_known = 1.0, 1.0, 1, None


TRIES_AT_SHOT_START = 10
"""A cheap try (the field model, the known cameras' guesses) runs on every frame of a shot it cannot place, this many
times, before it backs off: a shot is to be locked within its first 10 frames, and after the search at a shot's first
frame the budget waits, so these are what can still find its camera on the next frames (a try costs a few tracked
frames: a shot that cannot be placed costs about what detection costs)."""


@dataclass
class TrySchedule:
    """Which frames a cheap try runs on: the learned field model (tens of milliseconds, and a refinement on the
    marking map), or the guesses of every known camera at a shot's start (a refinement each on the marking map: with
    a match's several cameras, a tenth of a second or more a frame).

    After a cut or a view change (:meth:`new_stretch`) it tries every frame it cannot place, up to
    ``tries_at_shot_start`` of them; after that, and after a confident frame (:meth:`confident`), a frame it cannot
    place makes it wait 1, 2, 4, ... frames (at most ``max_gap_frames``). A frame it places restarts the wait.
    """

    tries_at_shot_start: int = TRIES_AT_SHOT_START
    max_gap_frames: int = 8
    _next: int = 0
    _gap: int = 1
    _tries_left: int | None = None  # None: a new stretch (the run's first frames)

    def allows(self, frame_index: int) -> bool:
        """The try may run on this frame."""
        return frame_index >= self._next

    def tried(self, frame_index: int, placed: bool) -> None:
        """The try ran on frame_index; placed: it gave a confident camera."""
        if placed:
            self._next, self._gap = 0, 1
            return
        tries_left = self.tries_at_shot_start if self._tries_left is None else self._tries_left
        if tries_left > 0:
            self._tries_left, self._next = tries_left - 1, frame_index + 1
            return
        self._tries_left, self._next = 0, frame_index + self._gap
        self._gap = min(2 * self._gap, self.max_gap_frames)

    def new_stretch(self) -> None:
        """A cut or a view change: the shot's first frames are tried one by one."""
        self._next, self._gap, self._tries_left = 0, 1, None

    def confident(self) -> None:
        """A confident frame: a later loss is tried after 1, 2, 4, ... frames."""
        self._next, self._gap, self._tries_left = 0, 1, 0
