"""Extract the MATLAB reference positions, velocities and accelerations of PMKS+'s verification set.

Source: PMKS-Web/PMKS_Verification, ``reference-data/v1/cases/<case>/`` at commit
932951a5316b16bfa41b937b04592c974143c4bb (the commit PMKS+ pins in src/test-data/verification/README.md), files
``case.json`` (the mechanism), ``matlab/samples.csv`` (one row per 1° input step) and ``matlab/joints/*.csv``,
``matlab/points/*.csv`` (x, y, vx, vy, ax, ay per sample, SI). Every 5th sample is kept (all of a short sweep).

Run once from a checkout of that repository:  python extract.py /path/to/PMKS_Verification
"""
import csv
import json
import subprocess
import sys
from io import StringIO
from pathlib import Path

COMMIT = "932951a5316b16bfa41b937b04592c974143c4bb"
CASES = ("teaching_four_bar", "teaching_slider_crank", "slider_crank_tracer", "stephenson_iii_example_2", "watt_i")


def show(repo, path):
    return subprocess.run(["git", "-C", repo, "show", f"{COMMIT}:{path}"], capture_output=True, encoding="utf-8",
                          check=True).stdout


def main(repo):
    here = Path(__file__).parent
    for case in CASES:
        base = f"reference-data/v1/cases/{case}"
        spec = json.loads(show(repo, f"{base}/case.json"))
        keep = {k: spec[k] for k in ("case_id", "title", "units", "characteristic_length", "topology", "input")}
        keep["source"] = f"PMKS-Web/PMKS_Verification@{COMMIT}:{base}/case.json"
        (here / f"{case}.json").write_text(json.dumps(keep, indent=1) + "\n", encoding="utf-8")
        samples = list(csv.DictReader(StringIO(show(repo, f"{base}/matlab/samples.csv"))))
        names = [j["id"] for j in spec["topology"]["joints"]] + [p["id"] for p in spec["topology"]["points"]]
        series = {}
        for n in names:
            kind = "joints" if any(j["id"] == n for j in spec["topology"]["joints"]) else "points"
            series[n] = {r["sample_id"]: r for r in csv.DictReader(StringIO(show(repo, f"{base}/matlab/{kind}/{n}.csv")))}
        step = 5 if len(samples) > 60 else 1
        with open(here / f"{case}.csv", "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(["sample_id", "input_angle_rad", "input_direction"]
                       + [f"{n}.{c}" for n in names for c in ("x", "y", "vx", "vy", "ax", "ay")])
            for k, s in enumerate(samples):
                if k % step and k != len(samples) - 1:
                    continue
                sid = s["sample_id"]
                if not all(sid in series[n] for n in names):
                    continue
                w.writerow([sid, s["input_angle_rad"], s["input_direction"]]
                           + [series[n][sid][c] for n in names for c in ("x", "y", "vx", "vy", "ax", "ay")])


if __name__ == "__main__":
    main(sys.argv[1])
