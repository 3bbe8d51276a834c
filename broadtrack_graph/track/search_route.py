"""The global search of re-initialisation: its stages, run in order, and the budget that decides when it is paid.

:class:`SearchRoute` is the last route of :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` (after the
guesses, the court model and the field model): it runs a :class:`~broadtrack_graph.track.search_stages.SearchPlan`'s
stages in order and keeps the best camera.

Which camera a search keeps: the best of its stages' (:mod:`~broadtrack_graph.track.search_stages`). The search ends
at the first stage whose best camera reaches ``certain_confidence`` for a new shot (``confidence_threshold``
mid-shot), or a known camera found at its own position confident by ``reinit_switch_margin``. A plan that looks for a
returning camera only (a new shot where the court model looks) keeps only the latter.
Without a marking map (keypoints or labelled lines of a detections file) the plan is cheap and labelled: the known
cameras' positions, then the default positions (mirrored too) only.

The budget (:class:`~broadtrack_graph.track.search_budget.SearchBudget`, in frames: the same cameras on any machine)
is paid in stages: a search that finds a camera its chain is trusted from restarts it, one that does not makes the
next wait longer; a shot's first search on a marking map leaves the bucket empty. No I/O.
"""

from __future__ import annotations

from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.search_budget import SearchBudget
from broadtrack_graph.track.search_stages import KNOWN_CAMERAS


class SearchRoute:
    """The global search in stages within its budget (module docstring).

    Args:
        config: ``global_search``, ``confidence_threshold``, ``reinit_switch_margin``, ``certain_confidence``,
            ``search_time_share``, ``search_cost_frames``, ``max_search_backoff``.
        search: one global search, ``(observations, detections, pitch, positions, curves, sampling) -> ReinitResult``
            (positions: a stage's candidate focal points, None for the default ones).
        registry: the run's cameras by id (a returning camera is recognised where it stands).
        counts: the policy's counters (``global``, ``stages``, ``skipped_by_budget``), updated here.
    """

    def __init__(self, config: TrackingConfig, search, registry: CameraRegistry, counts: dict) -> None:
        self.config = config
        self.search = search
        self.registry = registry
        self.counts = counts
        share = min(max(config.search_time_share, 1e-3), 1.0)
        self.budget = SearchBudget(config.search_cost_frames * (1.0 - share) / share, config.max_search_backoff)
        self.shot_searched = False  # the shot's first search on a marking map has run

    def new_stretch(self) -> None:
        """A cut or a view change: the next search is a shot's first, paid now."""
        self.shot_searched = False
        self.budget.restart()

    def confident(self) -> None:
        """A frame whose camera the tracker trusts: the budget restarts."""
        self.budget.restart()

    def not_searched_because(self, frame_index: int, known: bool) -> str | None:
        """Why a frame with a marking map is not searched (the search off, or its budget spent), or None."""
        if not self.config.global_search:
            return "no global search"
        if not self.budget.allows(frame_index, known):
            self.counts["skipped_by_budget"] += 1
            return f"search budget: the next global search at frame {self.budget.next_frame(frame_index, known)}"
        return None

    def run(self, plan, frame_index: int, known: bool, with_map: bool, trusted_from: float, frame: tuple,
            score) -> tuple[ReinitResult | None, float, str]:
        """Search the plan on a frame and pay for it: (the best camera's result or None, its confidence, one line).

        Args:
            plan: the :class:`~broadtrack_graph.track.search_stages.SearchPlan`.
            frame_index: the frame (the budget's clock); known: the chain's camera is a known one.
            with_map: the frame has a marking map (without one the search is cheap and not budgeted).
            trusted_from: the confidence a found camera's chain is trusted from (the budget counts it as found).
            frame: (observations, detections, pitch, curves, sampling) of the frame.
            score: the tracker's confidence of a camera on this frame (None without a marking map).
        """
        paid_before, shot_start = self.counts["stages"], plan.new_shot and not self.shot_searched
        found, found_confidence, label = self._stages(plan, *frame, score)
        self.shot_searched = self.shot_searched or shot_start
        self.counts["global"] += 1
        if with_map:
            self.budget.spend(frame_index, found is not None and found_confidence >= trusted_from,
                              self.counts["stages"] - paid_before, known, shot_start)
        return found, found_confidence, label

    def _stages(self, plan, observations, detections, pitch, curves, sampling,
                score) -> tuple[ReinitResult | None, float, str]:
        """The plan's stages, in order, until one is confident enough (module docstring): (best result or None, its
        confidence, one line).

        Without a marking map (keypoints or labelled lines of a detections file) the plan is cheap and
        labelled: the known cameras' positions, then the default positions (mirrored too) only.
        """
        threshold, margin = self.config.confidence_threshold, self.config.reinit_switch_margin
        enough = self.config.certain_confidence if plan.new_shot else threshold
        best, best_confidence, label, reasons, best_known = None, 0.0, "", [], False
        for stage_label, positions in plan.stages:
            result = self.search(observations, detections, pitch, positions, curves, sampling)
            self.counts["stages"] += 1
            if result.camera is None:
                reasons.append(f"{stage_label}: {result.reason}")
                continue
            confidence = score(result.camera)
            if confidence is None:  # no marking map: the search's own score
                confidence = result.score.jaccard if result.score is not None else 0.0
            if best is None or confidence > best_confidence:
                best, best_confidence = result, float(confidence)
                label = f"global search, {stage_label}: {result.reason}"
                best_known = stage_label == KNOWN_CAMERAS and self.registry.nearest(  # a returning camera
                    result.camera.position_m, result.camera.R_cw[2]) is not None
            if best is not None and best_confidence >= (threshold + margin if best_known else enough):
                break
        if best is None:
            why = "; ".join(dict.fromkeys(r.split(": ", 1)[-1] for r in reasons)) or "nothing found"
            return None, 0.0, why
        if plan.returning_only and not (best_known and best_confidence >= threshold + margin):
            return None, 0.0, f"no known camera explains the frame where it stands (best {best_confidence:.2f})"
        return best, best_confidence, label
