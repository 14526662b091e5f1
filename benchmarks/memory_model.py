#!/usr/bin/env python3
"""The memory model behind the check that refuses a scene too large for the machine
(include/feticontact/core/memory_estimate.h): measured peaks against the model's estimate.

    python3 benchmarks/memory_model.py [--exe build/feticontact] [--prm-dir prm]
        [--cases all|quick] [--csv doc/reports/data/memory_model.csv]
        [--markdown doc/reports/data/memory_model.md] [--report-only]

Every case runs the program once (one MSA step, `Contact solver/Maximum MSA iterations = 1`:
the meshes, the factors and the QP vectors all exist by then, and later steps allocate nothing
of size), reads from summary.json the peak resident set of the largest rank
(`memory.peak_rss_mib_max`) and the model's terms (`memory.model_cells` Σ C_b and
`memory.model_factor_units` Σ P_b (3 V_b / P_b)^(4/3) / np), and fits

    M = M₀ + a Σ C_b + b_f Σ P_b (3 V_b / P_b)^(4/3) / np

by least squares on the relative error (each row divided by its measured peak). The table gives
each case's peak, the estimate of the program that ran (`memory.estimated_peak_mib`, from the
coefficients compiled into it), the fitted model and both relative errors. The cases vary the
subdomain size (blocks of 3 … 192 subdomains), the number of ranks (1, 2), the number of bodies
(two_blocks.prm) and the mesh source (a Gmsh file). The CSV is rewritten after every case;
--report-only writes the tables from it. Standard library only.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402

arguments(__doc__, ["--exe", "--prm-dir", "--cases", "--csv", "--markdown"], ["--report-only"])

EXE = option("--exe", "build/feticontact")
PRM = option("--prm-dir", "prm")
CSV = option("--csv", "doc/reports/data/memory_model.csv")
MD = option("--markdown", "doc/reports/data/memory_model.md")


def brick(k, blocks):
    return ["Body 1/Mesh/Subdivisions=%d, %d, %d" % (3 * k, k, k),
            "Body 1/Decomposition/Method=blocks",
            "Body 1/Decomposition/Blocks=%d, %d, %d" % blocks,
            "Contact solver/Algorithm=mpgp"]


# name, parameter file, --set entries, ranks
CASES = [
    ("brick k=8, 3 parts", "kucera_table_2.prm", brick(8, (3, 1, 1)), 1),
    ("brick k=16, 3 parts", "kucera_table_2.prm", brick(16, (3, 1, 1)), 1),
    ("brick k=16, 24 parts", "kucera_table_2.prm", brick(16, (6, 2, 2)), 1),
    ("brick k=16, 81 parts", "kucera_table_2.prm", brick(16, (9, 3, 3)), 1),
    ("brick k=24, 3 parts", "kucera_table_2.prm", brick(24, (3, 1, 1)), 1),
    ("brick k=24, 24 parts", "kucera_table_2.prm", brick(24, (6, 2, 2)), 1),
    ("brick k=24, 81 parts", "kucera_table_2.prm", brick(24, (9, 3, 3)), 1),
    ("brick k=32, 24 parts", "kucera_table_2.prm", brick(32, (6, 2, 2)), 1),
    ("brick k=32, 192 parts", "kucera_table_2.prm", brick(32, (12, 4, 4)), 1),
    ("brick k=24, 24 parts, 2 ranks", "kucera_table_2.prm", brick(24, (6, 2, 2)), 2),
    ("brick k=32, 192 parts, 2 ranks", "kucera_table_2.prm", brick(32, (12, 4, 4)), 2),
    ("two blocks", "two_blocks.prm", [], 1),
    ("Gmsh brick", "brick_gmsh_contact.prm", [], 1),
]
QUICK = {"brick k=8, 3 parts", "brick k=16, 24 parts", "two blocks", "Gmsh brick"}
FIELDS = ["case", "ranks", "cells", "factor_units", "peak_mib", "estimate_mib"]


def run_case(prm, sets, ranks):
    with tempfile.TemporaryDirectory(prefix="memory_model_") as out:
        command = ([] if ranks == 1 else ["mpirun", "-np", str(ranks)]) + [EXE]
        for s in sets + ["Contact solver/Maximum MSA iterations=1", "Output/Directory=" + out]:
            command += ["--set", s]
        command.append(os.path.join(PRM, prm))
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
                   OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        result = subprocess.run(command, env=env, capture_output=True, text=True)
        path = os.path.join(out, "summary.json")
        if not os.path.exists(path):
            raise SystemExit(f"{' '.join(command)} wrote no summary.json (exit {result.returncode}):"
                             f"\n{result.stderr}")
        with open(path) as f:
            memory = json.load(f)["memory"]
    return {"cells": memory["model_cells"], "factor_units": memory["model_factor_units"],
            "peak_mib": memory["peak_rss_mib_max"], "estimate_mib": memory["estimated_peak_mib"]}


def solve3(a, b):
    """Gaussian elimination with partial pivoting for a 3 × 3 system."""
    m = [row[:] + [rhs] for row, rhs in zip(a, b)]
    for c in range(3):
        p = max(range(c, 3), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, 3):
            f = m[r][c] / m[c][c]
            m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    x = [0.0] * 3
    for r in (2, 1, 0):
        x[r] = (m[r][3] - sum(m[r][c] * x[c] for c in range(r + 1, 3))) / m[r][r]
    return x


def fit(rows):
    """M₀, a, b_f minimizing Σ ((M₀ + a C + b_f U) / peak − 1)²."""
    features = [[1 / r["peak_mib"], r["cells"] / r["peak_mib"], r["factor_units"] / r["peak_mib"]]
                for r in rows]
    ata = [[sum(f[i] * f[j] for f in features) for j in range(3)] for i in range(3)]
    atb = [sum(f[i] for f in features) for i in range(3)]
    return solve3(ata, atb)


def report(rows):
    m0, a, b = fit(rows)
    command = " ".join(["python3"] + sys.argv)
    out = ["<!-- written by benchmarks/memory_model.py -->", "",
           f"Command: `{command}`. Peak resident set of the largest rank (MiB) after one MSA step "
           "(brick cases: MPGP, blocks as given); 'compiled' is the estimate of the program "
           "that ran, 'fit' the least-squares model of these rows.", "",
           f"Fit: M₀ = {m0:.0f} MiB, a = {a:.3e} MiB per tetrahedron, "
           f"b_f = {b:.3e} MiB per factor unit.", "",
           "| case | ranks | tetrahedra | factor units per rank | peak | compiled | "
           "compiled / peak | fit | fit / peak |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        model = m0 + a * r["cells"] + b * r["factor_units"]
        out.append(f"| {r['case']} | {r['ranks']} | {r['cells']:.0f} | {r['factor_units']:.3g} | "
                   f"{r['peak_mib']:.0f} | {r['estimate_mib']:.0f} | "
                   f"{r['estimate_mib'] / r['peak_mib']:.2f} | {model:.0f} | "
                   f"{model / r['peak_mib']:.2f} |")
    text = "\n".join(out) + "\n"
    with open(MD, "w") as f:
        f.write(text)
    print(text)


def read_csv():
    with open(CSV) as f:
        return [{k: (v if k == "case" else float(v)) for k, v in row.items()}
                for row in csv.DictReader(f)]


def write_csv(rows):
    os.makedirs(os.path.dirname(CSV) or ".", exist_ok=True)
    with open(CSV, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: r[k] for k in FIELDS})


def main():
    if "--report-only" in sys.argv:
        report(read_csv())
        return
    quick = option("--cases", "all") == "quick"
    rows = []
    for name, prm, sets, ranks in CASES:
        if quick and name not in QUICK:
            continue
        row = dict(case=name, ranks=ranks, **run_case(prm, sets, ranks))
        rows.append(row)
        print(f"{name}: peak {row['peak_mib']:.0f} MiB, estimate {row['estimate_mib']:.0f} MiB",
              flush=True)
        write_csv(rows)
    report(rows)


if __name__ == "__main__":
    main()
