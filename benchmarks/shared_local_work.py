#!/usr/bin/env python3
"""The local work shared by the ranks of a node (FETI/Shared local work) against every rank
solving its own subdomains, on two ranks: the brick of benchmarks/scaling.py (fixed H/h,
8 × 8 × 8 cells per subdomain, friction coefficient μ = 0.3) with the solver's defaults
(the penalty factor of --penalty-factor if given).

    python3 benchmarks/shared_local_work.py [--exe build/feticontact] [--a 3,4]
        [--fractions 0.25,0] [--pairs 6] [--penalty-factor 3] [--csv doc/reports/data/shared_local_work.csv]
        [--markdown doc/reports/data/shared_local_work.md]

For every a of --a, --pairs rounds; each round runs every fraction of --fractions once, in that
order, so that a drift of the machine's speed touches all fractions alike. Rows of the CSV: one
per run (times from summary.json); the markdown table has the medians per fraction and how many
rounds each fraction won (the shortest total of its round). Standard library only.
"""
import csv
import os
import statistics
import subprocess
import tempfile

import scaling
from cli import arguments, option

# The MPGP, SMALBE and Expert values of the defaults; the penalty factor from --penalty-factor (empty: the default).
DEFAULTS = ("projected cg", "max", "0.001", "0.1", "mean diagonal", "", "", "")
FIELDS = ["a", "k", "fraction", "round", "n_A", "total", "solve", "hessian", "local_slowest",
          "local_fastest", "bookkeeping", "factorization", "solves_rank0", "solves_rank1"]


def run(exe, a, fraction):
    k, blocks = 8 * a, (3 * a, a, a)
    with tempfile.TemporaryDirectory() as out:
        command = scaling.contact_command(exe, k, blocks, out, DEFAULTS[:6] +
                                          (option("--penalty-factor", ""), ""))
        command = (["mpirun", "-np", "2", "--bind-to", "core"] + command[:-1] +
                   ["--set", f"FETI/Shared local work={fraction}", command[-1]])
        p = subprocess.run(command, capture_output=True, text=True, env=scaling.env())
        s = scaling.read_summary(p, command, out)
    t = s["times"]
    solves = s["local_work"]["subdomain_solves_per_rank"]
    return {"a": a, "k": k, "fraction": fraction, "n_A": s["hessian_multiplications"]["total"],
            "total": t["total"], "solve": t["solve"], "hessian": t["hessian_applications"],
            "local_slowest": t["hessian_local_slowest_rank"],
            "local_fastest": t["hessian_local_fastest_rank"], "bookkeeping": t["qp_bookkeeping"],
            "factorization": t["factorization"], "solves_rank0": solves[0],
            "solves_rank1": solves[1]}


def report(rows, path, command):
    with open(path, "w") as f:
        f.write("<!-- written by benchmarks/shared_local_work.py -->\n\n")
        f.write(f"Written by `{command}`. Two ranks, brick with 8 × 8 × 8 cells per subdomain, "
                "μ = 0.3, the solver's defaults" + (f" but penalty factor {option('--penalty-factor', '')}"
                                               if option("--penalty-factor", "") else "") +
                "; times [s] from summary.json, medians over the "
                "rounds; 'won' = rounds in which this fraction had the shortest total.\n\n")
        f.write("| k | FETI/Shared local work | rounds | won | total | applications of F | "
                "local work, slower rank | local work, faster rank | bookkeeping | "
                "factorization | n_A |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        for k in sorted({r["k"] for r in rows}):
            at_k = [r for r in rows if r["k"] == k]
            rounds = sorted({r["round"] for r in at_k})
            winners = [min((r for r in at_k if r["round"] == q), key=lambda r: r["total"])
                       ["fraction"] for q in rounds]
            for fraction in sorted({r["fraction"] for r in at_k}, reverse=True):
                runs = [r for r in at_k if r["fraction"] == fraction]
                med = {key: statistics.median(float(r[key]) for r in runs)
                       for key in ["total", "hessian", "local_slowest", "local_fastest",
                                   "bookkeeping", "factorization"]}
                f.write(f"| {k} | {fraction} | {len(runs)} | {winners.count(fraction)} | "
                        f"{med['total']:.2f} | {med['hessian']:.2f} | "
                        f"{med['local_slowest']:.2f} | {med['local_fastest']:.2f} | "
                        f"{med['bookkeeping']:.2f} | {med['factorization']:.2f} | "
                        f"{runs[0]['n_A']} |\n")


def main():
    arguments(__doc__, ["--exe", "--a", "--fractions", "--pairs", "--csv", "--markdown",
                        "--penalty-factor"])
    exe = option("--exe", "build/feticontact")
    sizes = [int(a) for a in option("--a", "3,4").split(",")]
    fractions = option("--fractions", "0.25,0").split(",")
    pairs = int(option("--pairs", "6"))
    csv_path = option("--csv", "doc/reports/data/shared_local_work.csv")
    md_path = option("--markdown", "doc/reports/data/shared_local_work.md")
    command = ("python3 benchmarks/shared_local_work.py --exe " + exe + " --a " +
               ",".join(map(str, sizes)) + " --fractions " + ",".join(fractions) + " --pairs " +
               str(pairs) + " --csv " + csv_path + " --markdown " + md_path)
    rows = []
    for a in sizes:
        for q in range(pairs):
            for fraction in fractions:
                row = run(exe, a, fraction)
                row["round"] = q
                rows.append(row)
                print(row, flush=True)
                with open(csv_path, "w", newline="") as f:
                    w = csv.DictWriter(f, fieldnames=FIELDS)
                    w.writeheader()
                    w.writerows(rows)
    report(rows, md_path, command)


if __name__ == "__main__":
    main()
