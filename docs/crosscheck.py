"""Regenerate docs/crosscheck.md: assur against the peers' own numbers (tests/crosscheck/corpus.py).

    python docs/crosscheck.py            # writes docs/crosscheck.md (needs pylinkage: pip install 'assur[pylinkage]')
"""
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "crosscheck"))
import corpus  # noqa: E402

HEAD = """# Cross-tool verification: assur against pylinkage, PMKS+ and four-bar-rs

Every mechanism below comes from a peer's own published examples or verification set, is read by `assur import`
(`assur.interop`) and solved by assur, and its positions (velocities and accelerations where the peer publishes
them) are compared with the peer's own numbers. A difference is relative to the mechanism's size (velocity to
ω·size, acceleration to ω²·size); 1e-9 or less is agreement. Every larger one is explained under the table, and
each explanation is checked by an independent computation in `tests/crosscheck/test_crosscheck.py`.

- **pylinkage** (HugoFara/pylinkage, run live in the tests, one turn in 360 steps): its documented examples
  (`docs/examples/fourbar_linkage.py`, `inverted_stroke_engine.py`, `strider.py`; the docstring examples of
  `pylinkage.mechanism.fourbar` and `slider_crank`) imported as live objects, and the shipped assur examples written
  with `assur export --to pylinkage` and simulated by pylinkage's own `mechanism_from_json`.
- **PMKS+** (PMKS-Web): the MATLAB reference kinematics of its verification set (PMKS-Web/PMKS_Verification,
  reference-data/v1, 1° input steps; every 5th sample kept in `tests/crosscheck/data/pmks_verification/`), for the
  mechanism at the set's own coordinates and as the published share links of the same mechanisms (the production
  and the current galleries, `tests/crosscheck/data/pmks_fixture_urls.tsv`).
- **four-bar-rs** (KmolYuan/four-bar-rs): its RON test files (`tests/crosscheck/data/fourbar/`). four-bar-rs
  publishes no simulated numbers; the reference is its position formula (`curve_interval`, four-bar/src/mech/fb.rs)
  written out independently in the corpus.
- **Pyslvs** publishes no simulated numbers either; its example mechanisms are imported and solved in
  `tests/test_interop.py`.

Regenerate with `python docs/crosscheck.py`.
"""


def cell(text: str) -> str:
    return str(text).replace("|", "\\|")


def main() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        groups = corpus.all_rows()
    lines = [HEAD, "| mechanism | source | quantity | peer value | assur value | difference |", "|---|---|---|---|---|---|"]
    notes: list[str] = []
    for peer, rows in groups.items():
        for r in rows:
            diff = "—" if r.diff != r.diff else ("∞" if r.diff == float("inf") else f"{r.diff:.1e}")
            if r.note:
                if r.note not in notes:
                    notes.append(r.note)
                diff += f" [{notes.index(r.note) + 1}]"
            lines.append(f"| {cell(r.mechanism)} | {cell(peer + ': ' + r.source)} | {cell(r.quantity)} | "
                         f"{cell(r.peer)} | {cell(r.ours)} | {diff} |")
    lines += ["", "## Every disagreement, explained", ""]
    lines += [f"{k}. {n}" for k, n in enumerate(notes, 1)]
    lines += ["", TAIL]
    (HERE / "crosscheck.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


TAIL = """## Found on the way

- **pylinkage, its own example `fourbar_linkage.py`:** the linkage is a parallelogram (crank = rocker = 1, coupler =
  ground = 3) drawn folded flat at its change point. pylinkage follows whichever assembly is nearest the previous
  step, so a parallelogram can turn into an antiparallelogram wherever it passes flat; assur fixes the assembly
  once, and asks for a `[branches]` hint where the drawing cannot tell it.
- **pylinkage, its own example `strider.py` at its own 10 steps per turn:** pylinkage takes, at each step, the
  intersection nearest the previous position; with 36° steps, at the 7th step that is the other intersection of the
  right foot's dyad, and the foot stays on that assembly (3.4 away from where it was heading). At 1° steps (rows
  above) pylinkage keeps one assembly over the whole turn, the one assur imports and keeps by construction.
- **pylinkage's own conversion** `Linkage.to_hypergraph()` → `to_mechanism()` keeps a component's *current*
  position as its dimension; for the Strider's unassembled initial coordinates it builds another mechanism.
  `assur import` therefore reads a live `Linkage` component by component, from the components' dimensions.
- **assur (ours), fixed:** the branch certificate of a Newton-solved group (`engine/planar/newton_group.py`, the
  equilibrated Jacobian determinant against `tolerances.newton_certify = 1e-9`) was not free of units: its angle
  columns carried lengths, so a small mechanism was never certified, and PMKS+'s *Double butterfly linkage* (an
  eight-bar that no dyad reaches, 7 cm across, in the current gallery) solved to no valid position. Each body's
  angle column is now divided by the body's own size before the test (a pure number, the same at any size); the
  linkage assembles over its whole turn, at its own size and scaled by 10⁻³ … 10³ (`tests/test_scale.py`).
"""

if __name__ == "__main__":
    main()
