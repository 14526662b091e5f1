#!/usr/bin/env python3
"""The cost of the mortar rows (doc/validation.md, "Non-matching meshes"):

    /usr/bin/python3 benchmarks/mortar_cost.py [--exe build/feticontact]
        [--coupling build/benchmarks/mortar_coupling] [--sizes 20,40,80,160,316] [--repeats 3]
        [--markdown doc/reports/data/mortar_cost.md] [--csv doc/reports/data/mortar_cost.csv]

1. The search and integrals alone (benchmarks/mortar_coupling.cc): a flat slave square of N × N
   cells against a master of 1.4 N × 1.4 N cells with the other diagonals, median of --repeats;
   the time per slave node stays flat if the cost grows like n log n or slower.
2. Their share of whole runs at about 10⁵ unknowns: prm/hertz_two_bodies.prm with its
   subdivisions × 1.5 and prm/two_blocks_nonmatching.prm with its subdivisions × 4, one run each:
   times.contact_rows (the contact search, the mortar integrals and the rows of N, T1, T2) against
   times.total of summary.json.
Standard library only.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

from cli import arguments, option


def coupling_rows(binary, sizes, repeats):
    p = subprocess.run([binary, "--sizes", sizes, "--repeats", str(repeats)], capture_output=True,
                       text=True, check=True)
    return list(csv.DictReader(p.stdout.splitlines()))


def run_share(exe, prm, sets):
    with tempfile.TemporaryDirectory() as out:
        cmd = [exe, "--set", f"Output/Directory={out}", "--set", "Output/Write vtu=false"]
        for s in sets:
            cmd += ["--set", s]
        p = subprocess.run(cmd + [prm], capture_output=True, text=True,
                           env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if p.returncode != 0:
            raise SystemExit(f"{prm} failed ({p.returncode}):\n{p.stderr}")
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
    t = s["times"]
    return dict(scene=os.path.basename(prm), unknowns=s["n_primal"], nodes=s["m_contact"],
                rows=t["contact_rows"], total=t["total"], share=t["contact_rows"] / t["total"],
                n_A=s["hessian_multiplications"]["total"])


def main():
    arguments(__doc__, ["--exe", "--coupling", "--sizes", "--repeats", "--markdown", "--csv"])
    exe = option("--exe", "build/feticontact")
    binary = option("--coupling", "build/benchmarks/mortar_coupling")
    rows = coupling_rows(binary, option("--sizes", "20,40,80,160,316"),
                         int(option("--repeats", "3")))
    for r in rows:
        print(r, flush=True)
    shares = [run_share(exe, "prm/hertz_two_bodies.prm",
                        ["Body 1/Mesh/Subdivisions=24, 24, 24", "Body 2/Mesh/Subdivisions=30, 30, 30"]),
              run_share(exe, "prm/two_blocks_nonmatching.prm",
                        ["Body 1/Mesh/Subdivisions=64, 32, 16", "Body 2/Mesh/Subdivisions=24, 24, 12"])]
    for r in shares:
        print(r, flush=True)
    with open(option("--csv", "doc/reports/data/mortar_cost.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    out = ["<!-- written by benchmarks/mortar_cost.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "Search and integrals (Mortar::couple), flat squares, median of the repeats:", "",
           "| slave nodes | master nodes | segments | time [s] | µs per slave node |",
           "|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {int(r['n_slave_nodes']):,} | {int(r['n_master_nodes']):,} | "
                   f"{int(r['segments']):,} | {float(r['seconds']):.3g} | "
                   f"{float(r['microseconds_per_slave_node']):.3g} |")
    out += ["", "Share of whole runs (one run each, one BLAS thread):", "",
            "| scene | unknowns | contact multipliers | contact rows [s] | run [s] | share | n_A |",
            "|---|---|---|---|---|---|---|"]
    for r in shares:
        out.append(f"| {r['scene']} | {r['unknowns']:,} | {r['nodes']:,} | {r['rows']:.3g} | "
                   f"{r['total']:.3g} | {100 * r['share']:.1f} % | {r['n_A']} |")
    with open(option("--markdown", "doc/reports/data/mortar_cost.md"), "w") as f:
        f.write("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
