#!/usr/bin/env python3
"""The subdomain size of `Decomposition/Method = automatic`: the brick with Coulomb friction
(prm/brick_contact.prm, the defaults) split into cubic blocks of c × c × c cells for several c,
and into METIS parts of the same number of unknowns, with n_A, the cost of one application of
F, the factorization and the solve.

    /usr/bin/python3 benchmarks/subdomain_size.py [--exe build/feticontact] [--k 16,24]
        [--friction 0.3,0.1] [--edges 2,3,4,6,8,12] [--metis-edges 4,8] [--repeats 3]
        [--csv doc/reports/data/subdomain_size.csv] [--markdown doc/reports/data/subdomain_size.md]
        [--merge] [--report-only]

An edge c gives `Blocks` = (round(3k/c), round(k/c), round(k/c)), subdomains of about 3(c + 1)³
unknowns; for the edges of --metis-edges also METIS with that many parts.
Times are medians of --repeats runs, from summary.json: the solve (n_A × one application of F
plus the QP bookkeeping), the factorization, and `total` without output. The CSV is rewritten
after every run; --merge keeps the rows of the k not run again; --report-only rewrites the
table from it. Standard library only.
"""
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from rows import write_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIELDS = ["k", "friction", "method", "edge", "size", "parts", "n_subdomains", "n_primal", "run", "n_A",
          "one_F_s", "factorization_s", "solve_s", "total_s", "converged"]


def run(exe, k, friction, method, edge, directory):
    blocks = [max(1, round(n / edge)) for n in (3 * k, k, k)]
    parts = blocks[0] * blocks[1] * blocks[2]
    size = round(3 * (3 * k + 1) * (k + 1) * (k + 1) / parts)
    output = os.path.join(directory, "out")
    command = [exe, "--set", f"Output/Directory={output}", "--set", "Output/Write vtu=false",
               "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
               "--set", f"Contact/Zone 1/Friction coefficient={friction}",
               "--set", f"Body 1/Decomposition/Method={method}",
               "--set", f"Body 1/Decomposition/Blocks={blocks[0]}, {blocks[1]}, {blocks[2]}",
               "--set", f"Body 1/Decomposition/Number of parts={parts}",
               os.path.join(ROOT, "prm", "brick_contact.prm")]
    result = subprocess.run(command, capture_output=True, text=True)
    path = os.path.join(output, "summary.json")
    if not os.path.exists(path):
        raise SystemExit(f"k={k} {method} c={edge}: exit {result.returncode}\n{result.stderr[-2000:]}")
    with open(path, encoding="utf-8") as f:
        s = json.load(f)
    t = s["times"]
    return {"k": k, "friction": friction, "method": method, "edge": edge, "size": size,
            "parts": parts,
            "n_subdomains": s["n_subdomains"], "n_primal": s["n_primal"],
            "n_A": s["hessian_multiplications"]["total"],
            "one_F_s": t["one_hessian_application"], "factorization_s": t["factorization"],
            "solve_s": t["solve"], "total_s": t["total"] - t["output"],
            "converged": s["converged"]}


def report(rows, markdown):
    keys = list(dict.fromkeys((r["k"], r["friction"], r["method"], r["edge"]) for r in rows))
    lines = ["| k | F | method | c | unknowns per subdomain | subdomains | n_A | one F [ms] | "
             "n_A × F [s] | factorization [s] | solve [s] | total [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in keys:
        k, friction, method, edge = key
        sel = [r for r in rows if (r["k"], r["friction"], r["method"], r["edge"]) == key]

        def med(key):
            return statistics.median(float(r[key]) for r in sel)
        n_A = med("n_A")
        lines.append(f"| {k} | {friction} | {method} | {edge} | {sel[0]['size']} | "
                     f"{sel[0]['n_subdomains']} | {n_A:.0f} | "
                     f"{1e3 * med('one_F_s'):.2f} | {n_A * med('one_F_s'):.2f} | "
                     f"{med('factorization_s'):.2f} | {med('solve_s'):.2f} | {med('total_s'):.2f} |")
    text = ("Medians of the runs; `total` without output.\n\n" + "\n".join(lines) + "\n")
    with open(markdown, "w", encoding="utf-8") as f:
        f.write(text)
    print(text)


def main():
    arguments(__doc__, ["--exe", "--k", "--friction", "--edges", "--metis-edges", "--repeats", "--csv",
                        "--markdown"], ["--report-only", "--merge"])
    exe = os.path.abspath(option("--exe", os.path.join(ROOT, "build", "feticontact")))
    ks = [int(k) for k in option("--k", "16,24").split(",")]
    frictions = [float(f) for f in option("--friction", "0.3,0.1").split(",")]
    edges = [int(c) for c in option("--edges", "2,3,4,6,8,12").split(",")]
    metis_edges = [int(c) for c in option("--metis-edges", "4,8").split(",")]
    cases = [("blocks", c) for c in edges] + [("metis", c) for c in metis_edges]
    repeats = int(option("--repeats", "3"))
    csv_path = option("--csv", os.path.join(ROOT, "doc", "reports", "data", "subdomain_size.csv"))
    markdown = option("--markdown", os.path.join(ROOT, "doc", "reports", "data", "subdomain_size.md"))
    rows = []
    if os.path.exists(csv_path):
        with open(csv_path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    if "--report-only" not in sys.argv:
        rows = [r for r in rows if int(r["k"]) not in ks] if "--merge" in sys.argv else []
        with tempfile.TemporaryDirectory() as directory:
            for k in ks:
                for friction in frictions:
                    for method, edge in cases:
                        if edge > k:
                            continue
                        for repeat in range(repeats):
                            row = run(exe, k, friction, method, edge, directory)
                            row["run"] = repeat + 1
                            rows.append(row)
                            print(f"k={k} F={friction} {method} c={edge}: {row['n_subdomains']} "
                                  f"subdomains, n_A {row['n_A']}, solve {row['solve_s']:.2f} s",
                                  flush=True)
                            write_rows(csv_path, FIELDS, rows)
    report(rows, markdown)


if __name__ == "__main__":
    main()
