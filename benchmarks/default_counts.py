#!/usr/bin/env python3
"""Multiplications with the defaults: the brick with Coulomb friction (prm/brick_contact.prm)
with nothing set but the mesh and the friction coefficient μ, for several k and μ.

    /usr/bin/python3 benchmarks/default_counts.py [--exe build/feticontact]
        [--k 4,8,12,16,20,24,32,48] [--friction 0.3,0.1]
        [--csv doc/reports/data/default_counts.csv] [--markdown doc/reports/data/default_counts.md]
        [--merge] [--report-only]

Each (μ, k) is one run of

    <exe> prm/brick_contact.prm --set "Body 1/Mesh/Subdivisions=3k, k, k"
        --set "Contact/Zone 1/Friction coefficient=μ" --set "Output/Write vtu=false"
        --set "Output/Directory=<temporary>"

(the automatic decomposition: blocks of about 6 × 6 × 6 cubes). From its summary.json: n
(`n_primal`), the subdomains, n_A (`hessian_multiplications.total`), the MSA iterations
(`outer_iterations`) and the solve time. The counts do not depend on the machine's speed but on
the rounding of OpenBLAS's kernels (regenerate_doc.py runs with the AVX2 kernels;
doc/reports/data/blas_kernels.md); the solve time does (one run, whatever threads the machine offers). The CSV is rewritten after every run;
--merge keeps the rows of (μ, k) not run again; --report-only rewrites the table from the CSV.
Standard library only.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

from cli import arguments, option
from rows import write_rows

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
FIELDS = ["mu", "k", "n", "subdomains", "n_A", "msa", "solve_s", "converged"]


def run(exe, k, friction):
    with tempfile.TemporaryDirectory() as out:
        command = [exe, os.path.join(ROOT, "prm", "brick_contact.prm"),
                   "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
                   "--set", f"Contact/Zone 1/Friction coefficient={friction}",
                   "--set", "Output/Write vtu=false", "--set", f"Output/Directory={out}"]
        p = subprocess.run(command, capture_output=True, text=True)
        path = os.path.join(out, "summary.json")
        if p.returncode != 0 or not os.path.exists(path):
            raise SystemExit(f"run failed (exit {p.returncode}): {' '.join(command)}\n"
                             f"{p.stderr[-2000:]}")
        with open(path, encoding="utf-8") as f:
            s = json.load(f)
    return {"mu": friction, "k": k, "n": s["n_primal"], "subdomains": s["n_subdomains"],
            "n_A": s["hessian_multiplications"]["total"], "msa": s["outer_iterations"],
            "solve_s": round(s["times"]["solve"], 3), "converged": s["converged"]}


def report(rows, path):
    frictions = sorted({r["mu"] for r in rows}, key=lambda f: -float(f))
    by = {(str(r["mu"]), int(r["k"])): r for r in rows}
    lines = ["<!-- written by benchmarks/default_counts.py -->", "",
             "The brick with Coulomb friction (friction coefficient μ) with the defaults (prm/brick_contact.prm, nothing set "
             "but the mesh and the friction coefficient; automatic decomposition). n_A: Hessian "
             "multiplications, MSA: outer iterations; one run each.", "",
             "| k | n | subdomains | " +
             " | ".join(f"n_A, μ = {f} | MSA, μ = {f}" for f in frictions) + " |",
             "|" + "---|" * (3 + 2 * len(frictions))]
    for k in sorted({int(r["k"]) for r in rows}):
        first = next(by[(str(f), k)] for f in frictions if (str(f), k) in by)
        cells = [str(k), f"{int(first['n']):,}", f"{int(first['subdomains']):,}"]
        for f in frictions:
            r = by.get((str(f), k))
            cells += [f"{int(r['n_A']):,}", str(r["msa"])] if r else ["", ""]
        lines.append("| " + " | ".join(cells) + " |")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def main():
    arguments(__doc__, ["--exe", "--k", "--friction", "--csv", "--markdown"],
              ["--merge", "--report-only"])
    exe = os.path.abspath(option("--exe", os.path.join(ROOT, "build", "feticontact")))
    ks = [int(v) for v in option("--k", "4,8,12,16,20,24,32,48").split(",") if v]
    frictions = [v for v in option("--friction", "0.3,0.1").split(",") if v]
    csv_path = option("--csv", os.path.join(ROOT, "doc", "reports", "data", "default_counts.csv"))
    md_path = option("--markdown", os.path.join(ROOT, "doc", "reports", "data", "default_counts.md"))
    rows = []
    if ("--merge" in sys.argv or "--report-only" in sys.argv) and os.path.exists(csv_path):
        with open(csv_path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    if "--report-only" not in sys.argv:
        for friction in frictions:
            for k in ks:
                rows = [r for r in rows if (str(r["mu"]), int(r["k"])) != (friction, k)]
                rows.append(run(exe, k, friction))
                print(rows[-1], flush=True)
                write_rows(csv_path, FIELDS, rows)
    report(rows, md_path)


if __name__ == "__main__":
    main()
