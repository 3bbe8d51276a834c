"""The filter-vs-smoother notebook runs top to bottom and its own checks hold.

The notebook renders a 60-frame 1920x1080 clip and tracks it twice, so this test takes
about a minute on two cores: it is the one end-to-end check of the product (render,
detect, track online and smoothed, evaluate, plot, compare) that CI runs.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat", reason="nbformat is a test dependency (pip install -e .[test])")
nbclient = pytest.importorskip("nbclient", reason="nbclient is a test dependency (pip install -e .[test])")
pytest.importorskip("ipykernel", reason="ipykernel is a test dependency (pip install -e .[test])")

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "filter_vs_smoother.ipynb"
KERNEL_NAME = "broadtrack-graph-test"


def _kernelspec_for_this_interpreter(folder: Path) -> None:
    """A kernelspec that starts this very interpreter (the venv's), found first through JUPYTER_PATH."""
    spec_dir = folder / "kernels" / KERNEL_NAME
    spec_dir.mkdir(parents=True)
    spec = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            "display_name": "broadtrack-graph test kernel", "language": "python"}
    (spec_dir / "kernel.json").write_text(json.dumps(spec), encoding="utf-8")


def test_notebook_is_committed_without_outputs():
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    code_cells = [c for c in notebook.cells if c.cell_type == "code"]
    assert len(code_cells) >= 8
    assert all(not c.outputs and c.execution_count is None for c in code_cells), "clear the notebook's outputs"


def test_notebook_runs_and_its_checks_hold(tmp_path, monkeypatch):
    jupyter_dir = tmp_path / "jupyter"
    _kernelspec_for_this_interpreter(jupyter_dir)
    monkeypatch.setenv("JUPYTER_PATH", str(jupyter_dir))
    work = tmp_path / "work"
    work.mkdir()
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name=KERNEL_NAME,
                                     resources={"metadata": {"path": str(work)}})
    client.execute()  # raises CellExecutionError when a cell (including the final asserts) fails

    # The notebook wrote its files into the working directory, not beside itself.
    out = work / "filter_vs_smoother"
    for name in ("series.png", "errors.png", "focal_points.png", "compare/compare.json"):
        assert (out / name).stat().st_size > 1000, name
    assert any(out.glob("overlay_*.png"))

    # The final cell's figures, checked again here from its printed results.
    text = "".join(o.get("text", "") for o in notebook.cells[-1].outputs if o.get("output_type") == "stream")
    line = next(line for line in text.splitlines() if line.startswith("RESULTS "))
    results = json.loads(line.removeprefix("RESULTS "))
    for run in ("online", "fixed_lag"):
        assert results[f"completeness_{run}"] == 1.0
        assert 0.9 <= results[f"jac5_{run}"] <= 1.0
        assert results[f"jac5_{run}"] <= results[f"jac10_{run}"] <= 1.0
        assert 0.0 < results[f"mre_{run}_px"] < 2.0
    # The smoother ties each focal point to the later frames' (tighter), and adds no jitter beyond the sampling
    # spread of a 58-sample second-difference RMS (about 13 %): on a clean clip the filter is at the noise floor.
    assert 0.0 < results["focal_point_spread_fixed_lag_m"] < results["focal_point_spread_online_m"]
    assert 0.0 < results["pan_jitter_d2_fixed_lag_deg"] <= 1.25 * results["pan_jitter_d2_online_deg"]
    assert 0.0 < results["focal_jitter_d2_fixed_lag_px"] <= 1.25 * results["focal_jitter_d2_online_px"]
    assert "all checks passed" in text
