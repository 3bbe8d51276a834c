"""Plots of camera tracks (matplotlib, Agg backend): parameters over time and focal point positions.

Every function takes :class:`~broadtrack_graph.types.track_record.RunRecords` objects keyed by
run name and writes one PNG; nothing is shown on screen.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from broadtrack_graph.types.track_record import RunRecords

GROUND_TRUTH_NAME = "ground truth"

# (column of Track.states(), axis label)
SERIES = {
    "pan": (2, "pan (deg)"),
    "tilt": (3, "tilt (deg)"),
    "roll": (4, "roll (deg)"),
    "focal": (0, "focal length (px)"),
    "k1": (1, "k1"),
    "Cx": (5, "C x (m)"),
    "Cy": (6, "C y (m)"),
    "Cz": (7, "C z (m)"),
}


def _frame_axis(track: RunRecords, id_to_index: dict[str, int]) -> np.ndarray:
    """(N,) x values: the frame index the runs give the frame id (so a reference folder
    of camera files, whose index is the number in the file name, lines up), else its own index."""
    return np.array([id_to_index.get(r.frame_id, r.frame_index) for r in track.records], dtype=float)


def _id_to_index(tracks: dict[str, RunRecords]) -> dict[str, int]:
    table: dict[str, int] = {}
    for track in tracks.values():
        for record in track.records:
            table.setdefault(record.frame_id, record.frame_index)
    return table


def plot_track_series(
    tracks: dict[str, RunRecords],
    out_path: str | Path,
    ground_truth: RunRecords | None = None,
    series: tuple[str, ...] = ("pan", "tilt", "focal", "Cx", "Cy", "Cz"),
    title: str | None = None,
) -> Path:
    """Camera parameters over time, one panel per parameter, one line per run.

    Frames without a camera are gaps in the lines; re-initialised frames are marked
    with a dot. A confidence panel is added when any run has confidences.

    Args:
        tracks: run name -> track (cameras at any resolution: the focal length is
            shown at the first run's resolution).
        out_path: PNG to write.
        ground_truth: optional reference track drawn as a thin black line.
        series: names from :data:`SERIES`.

    Returns:
        out_path.
    """
    unknown = [s for s in series if s not in SERIES]
    if unknown:
        raise ValueError(f"unknown series {unknown}, expected some of {tuple(SERIES)}")
    if not tracks:
        raise ValueError("no track to plot")
    width_ref = next(iter(tracks.values())).width_px
    has_confidence = any(np.isfinite(t.confidences()).any() for t in tracks.values())
    panels = list(series) + (["confidence"] if has_confidence else [])
    fig, axes = plt.subplots(len(panels), 1, figsize=(11, 1.9 * len(panels) + 0.6), sharex=True, squeeze=False)
    axes = axes[:, 0]
    all_runs = list(tracks.items()) + ([(GROUND_TRUTH_NAME, ground_truth)] if ground_truth is not None else [])
    id_to_index = _id_to_index(tracks)
    for name, track in all_runs:
        x = _frame_axis(track, id_to_index)
        states = track.states()
        states[:, 0] *= width_ref / track.width_px
        is_truth = name == GROUND_TRUTH_NAME
        style = dict(color="black", linewidth=0.8, linestyle="--", zorder=5) if is_truth else dict(linewidth=1.2)
        reinit = np.array([r.reinitialised for r in track.records], dtype=bool)
        for ax, panel in zip(axes, panels):
            if panel == "confidence":
                if not is_truth:
                    ax.plot(x, track.confidences(), label=name, **style)
                continue
            column = SERIES[panel][0]
            line = ax.plot(x, states[:, column], label=name, **style)
            if reinit.any() and not is_truth:
                ax.plot(x[reinit], states[reinit, column], "o", markersize=3, color=line[0].get_color())
    for ax, panel in zip(axes, panels):
        ax.set_ylabel("confidence" if panel == "confidence" else SERIES[panel][1], fontsize=9)
        ax.grid(True, alpha=0.3)
        if panel == "confidence":
            ax.set_ylim(0, 1.02)
            ax.axhline(0.5, color="grey", linewidth=0.8, linestyle=":")
    axes[-1].set_xlabel("frame")
    axes[0].legend(loc="best", fontsize=8, ncol=min(4, len(all_runs)))
    axes[0].set_title(title or "camera parameters over time (dots: re-initialised frames)", fontsize=10)
    fig.tight_layout()
    out_path = Path(out_path)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_path, dpi=110)
    plt.close(fig)
    return out_path


def plot_focal_points(
    tracks: dict[str, RunRecords],
    out_path: str | Path,
    tripod_T_w: np.ndarray | None = None,
    ground_truth: RunRecords | None = None,
    title: str | None = None,
) -> Path:
    """Focal point positions C of every frame seen from above (x, y) and from the side (y, z).

    As in the BroadTrack paper's figure: a free per-frame focal point scatters, a
    tripod-constrained one stays on a small surface around the tripod point T.

    Args:
        tracks: run name -> track.
        out_path: PNG to write.
        tripod_T_w: (3,) tripod point to mark with a star, metres (pitch frame, z down).
        ground_truth: optional reference track (black dots).

    Returns:
        out_path.
    """
    if not tracks:
        raise ValueError("no track to plot")
    fig, (ax_xy, ax_yz) = plt.subplots(1, 2, figsize=(11, 4.8))
    all_runs = list(tracks.items()) + ([(GROUND_TRUTH_NAME, ground_truth)] if ground_truth is not None else [])
    for name, track in all_runs:
        states = track.states()
        positions = states[np.all(np.isfinite(states[:, 5:8]), axis=1), 5:8]
        if not len(positions):
            continue
        is_truth = name == GROUND_TRUTH_NAME
        kwargs = dict(s=14, color="lightgrey", edgecolor="black", linewidths=0.4, zorder=1) if is_truth else dict(s=6, alpha=0.7, zorder=3)
        label = f"{name} ({len(positions)} frames)"
        ax_xy.scatter(positions[:, 0], positions[:, 1], label=label, **kwargs)
        # Side view: height shown upwards (-z), as z points down in the pitch frame.
        ax_yz.scatter(positions[:, 1], -positions[:, 2], label=label, **kwargs)
    if tripod_T_w is not None:
        T = np.asarray(tripod_T_w, dtype=float).reshape(3)
        ax_xy.scatter([T[0]], [T[1]], marker="*", s=160, color="red", edgecolor="black", zorder=10, label="tripod T")
        ax_yz.scatter([T[1]], [-T[2]], marker="*", s=160, color="red", edgecolor="black", zorder=10, label="tripod T")
    ax_xy.set_xlabel("x (m)")
    ax_xy.set_ylabel("y (m)  (+y: near touchline)")
    ax_xy.set_title("focal points from above", fontsize=10)
    ax_xy.set_aspect("equal", adjustable="datalim")
    ax_xy.invert_yaxis()  # near touchline at the bottom, as in the bird's-eye view
    ax_yz.set_xlabel("y (m)")
    ax_yz.set_ylabel("height -z (m)")
    ax_yz.set_title("focal points from the side", fontsize=10)
    ax_yz.set_aspect("equal", adjustable="datalim")
    for ax in (ax_xy, ax_yz):
        ax.grid(True, alpha=0.3)
    handles, labels = ax_xy.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(5, len(labels)), fontsize=8)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    out_path = Path(out_path)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_path, dpi=110)
    plt.close(fig)
    return out_path
