#!/usr/bin/env python3
"""The coarse problem GGᵀ: a factor per rank, a factor per node, and MUMPS (doc/performance.md,
"The coarse problem past this machine"):

    /usr/bin/python3 benchmarks/coarse_problem.py [--binary build/benchmarks/coarse_problem]
        [--sizes 4,8,12,16,20,24] [--np 1,2,4] [--repeats 3]
        [--csv doc/reports/data/coarse_problem.csv] [--markdown doc/reports/data/coarse_problem.md]

Runs benchmarks/coarse_problem.cc (a cube of N³ cubic subdomains with six rigid modes each and
the rows of a coarse TFETI mesh) once per rank count of --np (`mpirun --oversubscribe -np P`
beyond the two cores, one OpenBLAS thread per rank): per size the setup (gather or distributed
assembly, and factorization) and one solve, by CHOLMOD on every rank ("replicated",
FETI/Coarse factor = per rank), by CHOLMOD once per node with the factor in shared memory
("per node", the default) and by MUMPS through Trilinos Amesos on the rows of each rank
("distributed"), medians of --repeats, each method in a process of its own (the sizes in
increasing order, so that the peak resident memory after a size is that of the size): the peak
of rank 0 and the largest of the other ranks' without the shared factor they map.
All solve the same system (the solution norms printed agree). Standard library only.
"""
import csv
import io
import os
import subprocess
import sys

from cli import arguments, option


def run(binary, ranks, sizes, repeats, method):
    command = [binary, "--sizes", sizes, "--repeats", str(repeats), "--methods", method]
    if ranks > 1:
        command = ["mpirun", "--oversubscribe", "-np", str(ranks)] + command
    p = subprocess.run(command, capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                                OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({p.returncode}):\n{p.stderr}")
    return list(csv.DictReader(io.StringIO(p.stdout)))


METHODS = ("replicated", "per-node", "distributed")


def main():
    arguments(__doc__, ["--binary", "--sizes", "--np", "--repeats", "--csv", "--markdown"])
    binary = option("--binary", "build/benchmarks/coarse_problem")
    sizes = option("--sizes", "4,8,12,16,20,24")
    rows = []
    for ranks in [int(p) for p in option("--np", "1,2,4").split(",")]:
        # One process per method: the peak memory (VmHWM) of a process only grows.
        for method in METHODS:
            rows += run(binary, ranks, sizes, int(option("--repeats", "3")), method)
        for r in rows[-len(METHODS) * len(sizes.split(",")):]:
            print(r, flush=True)
    with open(option("--csv", "doc/reports/data/coarse_problem.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    out = ["<!-- written by benchmarks/coarse_problem.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "Setup and one solve in seconds; peak resident memory in MiB, of rank 0 and of the "
           "largest other rank without the shared factor it maps.", "",
           "| subdomains | coarse unknowns | entries of G | ranks "
           "| setup: replicated / per node / distributed "
           "| solve: replicated / per node / distributed "
           "| peak rank 0: replicated / per node / distributed "
           "| peak other ranks: replicated / per node / distributed |",
           "|---|---|---|---|---|---|---|---|"]
    by_key = {(r["method"], r["ranks"], r["subdomains"]): r for r in rows}
    for r in rows:
        if r["method"] != "replicated":
            continue
        m = [by_key.get((method, r["ranks"], r["subdomains"])) for method in METHODS]
        if None in m:
            continue
        for other in m[1:]:
            if abs(float(r["solution_norm"]) / float(other["solution_norm"]) - 1) > 1e-8:
                raise SystemExit(f"the methods disagree at {r['subdomains']} subdomains")
        others = " / ".join(f"{float(x['peak_mib_others']):.0f}" for x in m) \
            if int(r["ranks"]) > 1 else "–"
        out.append(f"| {int(r['subdomains']):,} | {int(r['coarse_unknowns']):,} | "
                   f"{int(float(r['G_entries'])):,} | {r['ranks']} | "
                   + " / ".join(f"{float(x['setup_seconds']):.3g}" for x in m) + " | "
                   + " / ".join(f"{float(x['solve_seconds']):.2g}" for x in m) + " | "
                   + " / ".join(f"{float(x['peak_mib_rank0']):.0f}" for x in m) + " | "
                   + others + " |")
    with open(option("--markdown", "doc/reports/data/coarse_problem.md"), "w") as f:
        f.write("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
