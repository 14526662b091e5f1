#!/usr/bin/env python3
"""The coarse problem GGᵀ replicated against distributed (doc/performance.md, "The coarse
problem past one machine"):

    /usr/bin/python3 benchmarks/coarse_problem.py [--binary build/benchmarks/coarse_problem]
        [--sizes 4,8,12,16,20,24] [--np 1,2,4] [--repeats 3]
        [--csv doc/data/coarse_problem.csv] [--markdown doc/data/coarse_problem.md]

Runs benchmarks/coarse_problem.cc (a cube of N³ cubic subdomains with six rigid modes each and
the rows of a coarse TFETI mesh) once per rank count of --np (`mpirun --oversubscribe -np P`
beyond the two cores, one OpenBLAS thread per rank): per size the setup (gather or distributed
assembly, and factorization) and one solve, by CHOLMOD on every rank ("replicated") and by
MUMPS through Trilinos Amesos on the rows of each rank ("distributed"), medians of --repeats,
each method in a process of its own (the sizes in increasing order, so that the peak resident
memory of rank 0 after a size is that of the size).
Both solve the same system (the solution norms printed agree). Standard library only.
"""
import csv
import io
import os
import subprocess
import sys

from cli import arguments, option


def run(binary, ranks, sizes, repeats, skip):
    command = [binary, "--sizes", sizes, "--repeats", str(repeats), skip]
    if ranks > 1:
        command = ["mpirun", "--oversubscribe", "-np", str(ranks)] + command
    p = subprocess.run(command, capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                                OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"))
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({p.returncode}):\n{p.stderr}")
    return list(csv.DictReader(io.StringIO(p.stdout)))


def main():
    arguments(__doc__, ["--binary", "--sizes", "--np", "--repeats", "--csv", "--markdown"])
    binary = option("--binary", "build/benchmarks/coarse_problem")
    sizes = option("--sizes", "4,8,12,16,20,24")
    rows = []
    for ranks in [int(p) for p in option("--np", "1,2,4").split(",")]:
        # One process per method: the peak memory (VmHWM) of a process only grows.
        for skip in ("--skip-distributed", "--skip-replicated"):
            rows += run(binary, ranks, sizes, int(option("--repeats", "3")), skip)
        for r in rows[-2 * len(sizes.split(",")):]:
            print(r, flush=True)
    with open(option("--csv", "doc/data/coarse_problem.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    out = ["<!-- written by benchmarks/coarse_problem.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "| subdomains | coarse unknowns | entries of G | ranks | replicated setup [s] "
           "| replicated solve [s] | distributed setup [s] | distributed solve [s] "
           "| peak rank 0, replicated / distributed [MiB] |",
           "|---|---|---|---|---|---|---|---|---|"]
    by_key = {(r["method"], r["ranks"], r["subdomains"]): r for r in rows}
    for r in rows:
        if r["method"] != "replicated":
            continue
        d = by_key.get(("distributed", r["ranks"], r["subdomains"]))
        if d is None:
            continue
        if abs(float(r["solution_norm"]) / float(d["solution_norm"]) - 1) > 1e-8:
            raise SystemExit(f"the two methods disagree at {r['subdomains']} subdomains")
        out.append(f"| {int(r['subdomains']):,} | {int(r['coarse_unknowns']):,} | "
                   f"{int(float(r['G_entries'])):,} | {r['ranks']} | "
                   f"{float(r['setup_seconds']):.3g} | {float(r['solve_seconds']):.2g} | "
                   f"{float(d['setup_seconds']):.3g} | {float(d['solve_seconds']):.2g} | "
                   f"{float(r['peak_mib_rank0']):.0f} / {float(d['peak_mib_rank0']):.0f} |")
    with open(option("--markdown", "doc/data/coarse_problem.md"), "w") as f:
        f.write("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
