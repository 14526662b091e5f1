#!/usr/bin/env python3
"""How the counts and the solution follow OpenBLAS's kernels: every scene of prm/ run with the
AVX2 kernels and with the AVX-512 kernels, and the time of both on the brick.

    /usr/bin/python3 benchmarks/blas_kernels.py [--exe build/feticontact] [--prm-dir prm]
        [--kernels Haswell,SkylakeX] [--repeats 3] [--k 16]
        [--csv doc/reports/data/blas_kernels.csv] [--markdown doc/reports/data/blas_kernels.md] [--report-only]

OpenBLAS picks its kernels by the CPU at run time; OPENBLAS_CORETYPE overrides the choice
(Haswell: AVX2; SkylakeX: AVX-512, which needs a CPU with AVX-512). CHOLMOD factorizes and
solves with OpenBLAS's dense kernels, so the kernels change the rounding of every local solve.
Every scene of --prm-dir (one rank, `Output/Write vtu = false`) runs once per kernel; from
summary.json the MSA iterations (`outer_iterations`) and n_A (`hessian_multiplications.total`),
and from displacements.csv the largest difference of the displacements between the kernels,
relative to the largest displacement (vertices matched by body and position). Then the brick
(prm/brick_contact.prm at k = --k) runs --repeats times per kernel, the kernels alternating, and
the table gives the medians of `times.factorization` and `times.solve` (one thread per rank is
not forced: the machine's threads, as a user runs it). Both kernels must run on this CPU. The CSV
is rewritten after every run; --report-only writes the table from it. Standard library only.
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

arguments(__doc__, ["--exe", "--prm-dir", "--kernels", "--repeats", "--k", "--csv", "--markdown"],
          ["--report-only"])

EXE = option("--exe", "build/feticontact")
PRM_DIR = option("--prm-dir", "prm")
KERNELS = option("--kernels", "Haswell,SkylakeX").split(",")
REPEATS = int(option("--repeats", "3"))
K = int(option("--k", "16"))
CSV = option("--csv", "doc/reports/data/blas_kernels.csv")
MARKDOWN = option("--markdown", "doc/reports/data/blas_kernels.md")
FIELDS = ["case", "kernel", "run", "n", "outer_iterations", "n_A", "du_relative", "factorization",
          "solve"]


def run(prm, kernel, sets, folder):
    env = dict(os.environ, OPENBLAS_CORETYPE=kernel)
    command = [EXE, prm, "--set", f"Output/Directory={folder}", "--set", "Output/Write vtu=false",
               "--set", "Output/Write displacement csv=true"]
    for s in sets:
        command += ["--set", s]
    result = subprocess.run(command, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(f"{prm} with {kernel}: exit {result.returncode}\n{result.stderr}")
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(folder, "displacements.csv")) as f:
        u = {(r["body"], r["x"], r["y"], r["z"]): [float(r[c]) for c in ("ux", "uy", "uz")]
             for r in csv.DictReader(f)}
    return summary, u


def difference(u, v):
    scale = max(max(abs(c) for c in row) for row in u.values()) or 1
    if set(u) != set(v):
        raise SystemExit("the runs have different vertices")
    return max(abs(a - b) for key in u for a, b in zip(u[key], v[key])) / scale


def measure():
    rows = []

    def save():
        with open(CSV, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=FIELDS)
            writer.writeheader()
            writer.writerows(rows)

    scenes = sorted(p for p in os.listdir(PRM_DIR) if p.endswith(".prm"))
    for scene in scenes:
        results = {}
        for kernel in KERNELS:
            with tempfile.TemporaryDirectory() as folder:
                results[kernel] = run(os.path.join(PRM_DIR, scene), kernel, [], folder)
        first = results[KERNELS[0]][1]
        for kernel in KERNELS:
            summary, u = results[kernel]
            rows.append(dict(case=scene[:-4], kernel=kernel, run=1, n=summary["n_primal"],
                             outer_iterations=summary.get("outer_iterations", ""),
                             n_A=summary["hessian_multiplications"]["total"],
                             du_relative=f"{difference(first, u):.3e}",
                             factorization=summary["times"]["factorization"],
                             solve=summary["times"]["solve"]))
            print(rows[-1], flush=True)
        save()
    brick = os.path.join(PRM_DIR, "brick_contact.prm")
    for repeat in range(REPEATS):
        for kernel in KERNELS:
            with tempfile.TemporaryDirectory() as folder:
                summary, _ = run(brick, kernel, [f"Body 1/Mesh/Subdivisions={3 * K}, {K}, {K}"],
                                 folder)
            rows.append(dict(case=f"brick_contact k={K}", kernel=kernel, run=repeat + 1,
                             n=summary["n_primal"], outer_iterations=summary["outer_iterations"],
                             n_A=summary["hessian_multiplications"]["total"], du_relative="",
                             factorization=summary["times"]["factorization"],
                             solve=summary["times"]["solve"]))
            print(rows[-1], flush=True)
            save()


def report():
    with open(CSV) as f:
        rows = list(csv.DictReader(f))
    a, b = KERNELS[0], KERNELS[1]
    lines = [f"Counts with OpenBLAS's {a} and {b} kernels (OPENBLAS_CORETYPE), one rank; "
             f"`/usr/bin/python3 benchmarks/blas_kernels.py`.", "",
             f"| scene | n | MSA iterations, {a} / {b} | n_A, {a} / {b} | n_A change | "
             f"max \\|u_{b} − u_{a}\\| / max \\|u\\| |",
             "|---|---|---|---|---|---|"]
    cases = [r["case"] for r in rows if r["kernel"] == a and not r["case"].startswith("brick_contact k=")]
    changes = []
    for case in cases:
        ra = next(r for r in rows if r["case"] == case and r["kernel"] == a)
        rb = next(r for r in rows if r["case"] == case and r["kernel"] == b)
        na, nb = int(ra["n_A"]), int(rb["n_A"])
        change = (nb - na) / na if na else 0.0
        if na:
            changes.append(change)
        lines.append(f"| {case} | {int(ra['n']):,} | {ra['outer_iterations']} / "
                     f"{rb['outer_iterations']} | {na:,} / {nb:,} | "
                     f"{100 * change:+.1f} % | {float(rb['du_relative']):.1e} |")
    if changes:
        lines += ["", f"n_A changes by {100 * min(changes):+.1f} % to {100 * max(changes):+.1f} % "
                      f"({sum(1 for c in changes if c != 0)} of {len(changes)} scenes change)."]
    timed = [r for r in rows if r["case"].startswith("brick_contact k=")]
    if timed:
        lines += ["", f"Times of {timed[0]['case']} (medians of "
                      f"{max(int(r['run']) for r in timed)} runs, the kernels alternating):", "",
                  "| kernel | n_A | factorization [s] | solve [s] |", "|---|---|---|---|"]
        for kernel in KERNELS:
            mine = [r for r in timed if r["kernel"] == kernel]
            lines.append(f"| {kernel} | {mine[0]['n_A']} | "
                         f"{statistics.median(float(r['factorization']) for r in mine):.3f} | "
                         f"{statistics.median(float(r['solve']) for r in mine):.3f} |")
    with open(MARKDOWN, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    if "--report-only" not in sys.argv:
        with open("/proc/cpuinfo") as f:
            flags = f.read()
        if "SkylakeX" in KERNELS and " avx512f" not in flags:
            raise SystemExit("this CPU has no AVX-512: the SkylakeX kernels cannot run here")
        measure()
    report()
