"""Record the special points of the regression scenes (run on a commit whose outputs are trusted).

``python -m tests.regression.capture`` traces every scene of :data:`SCENES` through the command
line and writes ``tests/regression/<name>.json``: the located special points (kind, label, which
parameter folds, where, and the stability around them) and the scene's headline numbers.
``tests/test_regression.py`` traces the same scenes and compares.  The files were written on
commit 57912bb (before issue 14's redesign) and are not to be regenerated to make a test pass.

Issue 14 (B3) deliberately changed the indenter contact: the barrier sees the meridian between the
nodes.  The indenter scenes' points as they are since then were recorded into ``after_b3/`` by
``python -m tests.regression.capture --after-b3 sphere_0.5 sphere_1.1 plate`` on the merge of that
change.  Issue 14 (B8) changed the contact again: the meridian the barrier sees is the C1 quadratic
B-spline of the nodes, and the barrier is integrated over its support (where the meridian is within
``dhat``) instead of at fixed points.  The indenter scenes since then are in ``after_b8/``
(``python -m tests.regression.capture --after-b8 sphere_0.5 sphere_1.1 plate``); the test compares
them to 1e-8, and checks that the eversion snap ``w_b_c`` lies within 1e-3 R of the 57912bb
references.  ``after_b3/`` stays as the record of the intermediate state.

Issue 18 made the location of special points take each trial point's tangent from a linearization
at the point itself instead of from the corrector's last one, an update away.  The default scene's located extrema of F moved by
up to 1.6e-7 R, to the zeros of dF/dw that an independent computation finds
(``tests/test_located_extrema.py``).  That scene is in ``after_i18/``
(``python -m tests.regression.capture --after-i18 point_default``); the test compares it to 1e-8, and
compares it with the 57912bb reference to 1e-8 except at the extrema of F, which may move by 2e-7 R.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: name -> command-line overrides of the shell's default scene
SCENES: dict[str, list[str]] = {
    "point_default": [],
    "point_phi_1.2": ["shell.phi_hat=1.2"],
    "point_force": ["load.control=force"],
    "sphere_0.5": ["load.kind=sphere", "load.radius=0.5"],
    "sphere_1.1": ["load.kind=sphere", "load.radius=1.1"],
    "plate": ["load.kind=plate"],
}

#: fields of a special point that are compared (numbers to 1e-8, the rest exactly)
POINT_FIELDS = ("kind", "label", "parameter", "p", "w", "w_b", "F", "F_norm", "w_over_R", "w_b_over_R",
                "stable_before", "stable_after")
#: headline numbers of summary.json that are compared when present
SUMMARY_FIELDS = ("classification", "w_b_c", "F_at_snap", "Delta_H_at_snap", "w_c_one_sided")


def trace_summary(overrides: list[str]) -> dict:
    """Run ``contin trace`` in-process with the overrides and return its summary.json."""
    from contin.app.cli import main

    with tempfile.TemporaryDirectory() as tmp:
        argv = ["trace", "--out", tmp, "-q", "--set", "output.figure=false"]
        for item in overrides:
            argv += ["--set", item]
        status = main(argv)
        if status != 0:
            raise RuntimeError(f"contin {' '.join(argv)} exited {status}")
        return json.loads((Path(tmp) / "summary.json").read_text())


def extract(summary: dict) -> dict:
    """The compared part of a summary: special points in path order, headline numbers."""
    points = [{k: sp[k] for k in POINT_FIELDS if k in sp} for sp in summary["special_points"]
              if sp.get("located", True)]
    return {"special_points": points,
            "summary": {k: summary[k] for k in SUMMARY_FIELDS if k in summary}}


#: Scenes whose contact changed in issue 14 (B3, then B8), with their later references in these folders.
CHANGED_BY_B3 = ("sphere_0.5", "sphere_1.1", "plate")
AFTER_B3 = HERE / "after_b3"
AFTER_B8 = HERE / "after_b8"
#: Scenes whose located extrema of F moved by more than 1e-8 R in issue 18, when tangents came to be
#: linearized at their points (tests/test_located_extrema.py), and their later references.
CHANGED_BY_I18 = ("point_default",)
AFTER_I18 = HERE / "after_i18"
FOLDERS = {"--after-b3": AFTER_B3, "--after-b8": AFTER_B8, "--after-i18": AFTER_I18}


def main() -> int:
    args = sys.argv[1:]
    folder = HERE
    if args[:1] and args[0] in FOLDERS:
        folder, args = FOLDERS[args[0]], args[1:]
        folder.mkdir(exist_ok=True)
    for name in args or list(SCENES):
        record = extract(trace_summary(SCENES[name]))
        record["overrides"] = SCENES[name]
        (folder / f"{name}.json").write_text(json.dumps(record, indent=1) + "\n")
        print(f"{name}: {len(record['special_points'])} special points")
    return 0


if __name__ == "__main__":
    sys.exit(main())
