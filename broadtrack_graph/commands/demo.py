"""``broadtrack-graph demo``: the README's main command.

Until the tracker lands, the demo scores the published NBJW cameras against the real
SoccerNet annotations that sit beside the repository (../shared/data), with the
project's evaluator, and says so.
"""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.commands.evaluate import evaluate_folders
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import write_json_atomic

HELP = "run the main job on the embedded default and print where the results are"

REPO_ROOT = Path(__file__).resolve().parents[2]
REAL_DATA = REPO_ROOT.parent / "shared" / "data" / "sn-calibration-2022-test-main"


def add_arguments(parser) -> None:
    parser.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder (default runs/demo)")


def run(args) -> int:
    if not (REAL_DATA / "annotations").is_dir():
        raise InputError(REAL_DATA, "the interim demo needs the SoccerNet data beside the repository (not found)")
    print("demo (interim, until the tracker lands): scoring the published NBJW cameras against the real "
          "SoccerNet calibration test annotations with the project's evaluator")
    report = evaluate_folders(REAL_DATA / "annotations", REAL_DATA / "nbjw-cameras", 960, 540, (5, 10, 20))
    for key, row in report["taus"].items():
        print(f"  tau {key:>2} px: final score {row['final_score']:.4f}  completeness {row['completeness']:.4f}  "
              f"accuracy {row['accuracy']:.4f}  MRE {row['mre_px']:.2f} px")
    path = args.out / "evaluation.json"
    write_json_atomic(path, report, indent=1)
    print(f"report: {path}")
    return 0
