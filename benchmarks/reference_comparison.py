#!/usr/bin/env python3
"""The brick with Coulomb friction F = 0.3 on the Gmsh mesh tests/meshes/brick_k4.msh,
solved by every contact algorithm and compared with the independent reference solution
stored in tests/reference/ (GetFEM 5.4, nodal contact, Newton to 1e-12; tests/reference/README.md). Writes doc/reports/data/reference_comparison.md.

    python3 benchmarks/reference_comparison.py [--exe build/feticontact]

Standard library only; run from the repository root after building.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

exe = "build/feticontact"
if "--exe" in sys.argv:
    exe = sys.argv[sys.argv.index("--exe") + 1]
reference = "tests/reference/displacements_F0.3.csv"


def load(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {(round(float(r["x"]), 9), round(float(r["y"]), 9), round(float(r["z"]), 9)):
            [float(r[k]) for k in ("ux", "uy", "uz")] for r in rows}


ref = load(reference)
scale = max(abs(c) for u in ref.values() for c in u)
rows = []
settings = [("default (MSA 1e-6, QP 1e-8)", []),
            ("tight (MSA 1e-8, QP 1e-10)", ["--set", "Contact solver/MSA relative tolerance=1e-8",
                                             "--set", "Contact solver/QP relative tolerance=1e-10"])]
with tempfile.TemporaryDirectory() as tmp:
  for tolerances, extra in settings:
    for algorithm in ("algorithm 1", "algorithm 2", "mpgp", "polygonal"):
        out = os.path.join(tmp, "run")
        subprocess.run([exe, "--set", f"Output/Directory={out}", "--set",
                        f"Contact solver/Algorithm={algorithm}", "--set", "Output/Write vtu=false",
                        "--set", "Output/Write displacement csv=true", *extra,
                        "prm/brick_gmsh_contact.prm"], check=True, capture_output=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))  # as every study here
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        ours = load(os.path.join(out, "displacements.csv"))
        diff = max(abs(a - b) for p in ref for a, b in zip(ours[p], ref[p])) / scale
        rows.append((tolerances, algorithm, diff, s))
        print(tolerances, algorithm, diff, flush=True)

lines = ["| tolerances | algorithm | max ‖u − u_ref‖ / max ‖u_ref‖ | Iter | SMALBE iterations | n_A (bound + disc) "
         "| open / stick / slip | penetration | cone violation | time (s) |",
         "|---|---|---|---|---|---|---|---|---|---|"]
for tolerances, algorithm, diff, s in rows:
    h = s["hessian_multiplications"]
    c = s["contact"]
    k = s["kkt"]
    lines.append(f"| {tolerances} | {algorithm} | {diff:.1e} | {s['outer_iterations']} | {s['smalbe_iterations']} "
                 f"| {h['total']} ({h['bound']} + {h['disc']}) | {c['open']} / {c['stick']} / {c['slip']} "
                 f"| {k['penetration']:.1e} | {k['cone_violation']:.1e} | {s['times']['solve']:.2f} |")
os.makedirs("doc/reports/data", exist_ok=True)
with open("doc/reports/data/reference_comparison.md", "w") as f:
    f.write("<!-- written by: python3 benchmarks/reference_comparison.py -->\n")
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
