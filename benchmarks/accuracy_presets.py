#!/usr/bin/env python3
"""The presets of `Contact solver/Accuracy` (draft, engineering, reference): what each buys, and
that each converges on the mortar scenes.

    /usr/bin/python3 benchmarks/accuracy_presets.py [--exe build/feticontact] [--prm prm]
        [--scenes tests/scenes] [--k 8] [--markdown doc/reports/data/accuracy_presets.md] [--work DIR]

Part 1, on the paper's brick (prm/kucera_table_2.prm, Subdivisions 3k, k, k, Algorithm mpgp):
each preset against a reference solve of the same mesh at MSA = QP = 1e-12:
e_max = max_v |u − u_ref| / max_v |u_ref|, e_energy = ‖u − u_ref‖_K / ‖u_ref‖_K
(feticontact's Verification/Reference displacements), the contact nodes whose open/stick/slip
status differs from the reference, MSA steps and Hessian multiplications n_A.
Part 2: every preset on the scenes with mortar zones (prm/hertz_two_bodies.prm,
prm/cattaneo_mindlin_pair.prm, prm/two_blocks_nonmatching.prm, tests/scenes/hemisphere_pushed_sideways.prm):
exit status, MSA steps, n_A. Counts do not depend on the machine. Standard library only.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PRESETS = ("draft", "engineering", "reference")


def run(exe, prm, outdir, sets):
    cmd = [exe, "--set", f"Output/Directory={outdir}", "--set", "Output/Write vtu=false",
           *[a for s in sets for a in ("--set", s)], prm]
    p = subprocess.run(cmd, capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    summary = {}
    path = os.path.join(outdir, "summary.json")
    if os.path.exists(path):
        with open(path) as f:
            summary = json.load(f)
    return p.returncode, summary


def read_rows(path, key):
    with open(path) as f:
        return {key(r): r for r in csv.DictReader(f)}


def position(r):
    return tuple(round(float(r[c]), 9) for c in ("x", "y", "z"))


def brick(exe, prm_dir, k, work):
    prm = os.path.join(prm_dir, "kucera_table_2.prm")
    base = [f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}", "Contact solver/Algorithm=mpgp",
            "Output/Write displacement csv=true"]
    ref = os.path.join(work, "reference_1e-12")
    status, _ = run(exe, prm, ref, base + ["Contact solver/MSA relative tolerance=1e-12",
                                           "Contact solver/QP relative tolerance=1e-12"])
    if status != 0:
        raise SystemExit(f"the reference solve failed (exit {status})")
    u_ref = read_rows(os.path.join(ref, "displacements.csv"), position)
    c_ref = read_rows(os.path.join(ref, "contact.csv"), position)
    scale = max(math.sqrt(sum(float(r[c]) ** 2 for c in ("ux", "uy", "uz"))) for r in u_ref.values())
    lines = ["| Accuracy | e_max | e_energy | statuses differing | MSA steps | n_A |",
             "|---|---|---|---|---|---|"]
    for preset in PRESETS:
        out = os.path.join(work, preset)
        status, s = run(exe, prm, out, base + [f"Contact solver/Accuracy={preset}",
                                                f"Verification/Reference displacements="
                                                f"{os.path.join(ref, 'displacements.csv')}"])
        if status != 0:
            lines.append(f"| {preset} | exit {status} | | | | |")
            print(lines[-1], flush=True)
            continue
        u = read_rows(os.path.join(out, "displacements.csv"), position)
        c = read_rows(os.path.join(out, "contact.csv"), position)
        e_max = max(max(abs(float(u[x][a]) - float(r[a])) for a in ("ux", "uy", "uz"))
                    for x, r in u_ref.items()) / scale
        changes = sum(c[x]["status"] != r["status"] for x, r in c_ref.items())
        lines.append(f"| {preset} | {e_max:.1e} | "
                     f"{s['reference_difference']['energy_relative']:.1e} | {changes} | "
                     f"{s['outer_iterations']} | {s['hessian_multiplications']['total']:,} |")
        print(lines[-1], flush=True)
    return lines


def mortar(exe, prm_dir, scenes_dir, work):
    scenes = [os.path.join(prm_dir, n) for n in
              ("hertz_two_bodies.prm", "cattaneo_mindlin_pair.prm", "two_blocks_nonmatching.prm")]
    scenes.append(os.path.join(scenes_dir, "hemisphere_pushed_sideways.prm"))
    lines = ["| scene | " + " | ".join(PRESETS) + " |", "|---|" + "---|" * len(PRESETS)]
    for prm in scenes:
        cells = []
        for preset in PRESETS:
            name = os.path.splitext(os.path.basename(prm))[0]
            status, s = run(exe, prm, os.path.join(work, f"{name}_{preset}"),
                            [f"Contact solver/Accuracy={preset}", "Verification/Hertz/Enabled=false"]
                            if "hertz" in name else [f"Contact solver/Accuracy={preset}"])
            cells.append(f"exit {status}" + (f", {s['outer_iterations']} MSA, n_A "
                                             f"{s['hessian_multiplications']['total']:,}"
                                             if s.get("converged") else ""))
        lines.append(f"| {os.path.relpath(prm, ROOT)} | " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    return lines


def main():
    arguments(__doc__, ("--exe", "--prm", "--scenes", "--k", "--markdown", "--work"))
    exe = option("--exe", os.path.join(ROOT, "build", "feticontact"))
    prm_dir = option("--prm", os.path.join(ROOT, "prm"))
    scenes_dir = option("--scenes", os.path.join(ROOT, "tests", "scenes"))
    k = int(option("--k", "8"))
    markdown = option("--markdown", os.path.join(ROOT, "doc", "reports", "data", "accuracy_presets.md"))
    work = option("--work", tempfile.mkdtemp(prefix="accuracy_presets_"))
    lines = [f"The presets on the brick at k = {k} (prm/kucera_table_2.prm, Algorithm mpgp), "
             "against a reference solve at 1e-12:", ""]
    lines += brick(exe, prm_dir, k, os.path.join(work, "brick")) + [""]
    lines += ["Every preset on the scenes with mortar zones (exit status, MSA steps, n_A):", ""]
    lines += mortar(exe, prm_dir, scenes_dir, os.path.join(work, "mortar"))
    command = ("/usr/bin/python3 benchmarks/accuracy_presets.py" +
               ("" if k == 8 else f" --k {k}"))
    with open(markdown, "w") as f:
        f.write(f"<!-- written by {command} -->\n" + "\n".join(lines) + "\n")
    print(f"wrote {markdown}")


if __name__ == "__main__":
    main()
