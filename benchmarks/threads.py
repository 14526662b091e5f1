#!/usr/bin/env python3
"""The threads of the subdomains' local work: the default run (prm/brick_contact.prm, F = 0.3,
the defaults) at several k on one and on two threads (DEAL_II_NUM_THREADS), runs alternating,
with the time of one application of F, the local work, the factorization, the solve and the
process wall time, and whether the two give the same displacements to the last bit.

    /usr/bin/python3 benchmarks/threads.py [--exe build/feticontact] [--k 8,16,24]
        [--threads 1,2] [--repeats 3] [--markdown doc/reports/data/threads.md]

Times are medians of --repeats runs (summary.json; `wall` is the process wall time measured
here, start-up and output included). Standard library only.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(exe, k, threads, output):
    env = dict(os.environ, DEAL_II_NUM_THREADS=str(threads))
    command = [exe, "--set", f"Output/Directory={output}", "--set", "Output/Write vtu=false",
               "--set", "Output/Write displacement csv=true",
               "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
               os.path.join(ROOT, "prm", "brick_contact.prm")]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    if result.returncode != 0:
        raise SystemExit(f"k={k}, {threads} threads: exit {result.returncode}\n{result.stderr}")
    with open(os.path.join(output, "summary.json"), encoding="utf-8") as f:
        s = json.load(f)
    with open(os.path.join(output, "displacements.csv"), encoding="utf-8") as f:
        displacements = f.read()
    t = s["times"]
    return {"one_F": t["one_hessian_application"], "local": t["hessian_local_slowest_rank"],
            "factorization": t["factorization"], "assembly": t["assembly"],
            "solve": t["solve"], "wall": wall, "n_A": s["hessian_multiplications"]["total"],
            "n_subdomains": s["n_subdomains"], "n_primal": s["n_primal"],
            "threads": s.get("threads_per_rank")}, displacements


def main():
    arguments(__doc__, ["--exe", "--k", "--threads", "--repeats", "--markdown"])
    exe = os.path.abspath(option("--exe", os.path.join(ROOT, "build", "feticontact")))
    ks = [int(k) for k in option("--k", "8,16,24").split(",")]
    thread_counts = [int(t) for t in option("--threads", "1,2").split(",")]
    repeats = int(option("--repeats", "3"))
    markdown = option("--markdown", os.path.join(ROOT, "doc", "reports", "data", "threads.md"))
    lines = ["| k | n | subdomains | threads | n_A | one F [ms] | local work [s] | assembly [s] | "
             "factorization [s] | solve [s] | wall [s] | F speed-up | same bits |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as directory:
        for k in ks:
            rows = {t: [] for t in thread_counts}
            bits = {}
            for _ in range(repeats):
                for t in thread_counts:
                    row, u = run(exe, k, t, os.path.join(directory, f"k{k}_t{t}"))
                    rows[t].append(row)
                    bits[t] = u
            base = statistics.median(r["one_F"] for r in rows[thread_counts[0]])
            for t in thread_counts:
                med = {key: statistics.median(r[key] for r in rows[t])
                       for key in ("one_F", "local", "assembly", "factorization", "solve", "wall")}
                first = rows[t][0]
                lines.append(
                    f"| {k} | {first['n_primal']} | {first['n_subdomains']} | {first['threads']} | "
                    f"{first['n_A']} | {1e3 * med['one_F']:.3f} | {med['local']:.3f} | "
                    f"{med['assembly']:.3f} | {med['factorization']:.3f} | {med['solve']:.3f} | "
                    f"{med['wall']:.2f} | {base / med['one_F']:.2f} | "
                    f"{'yes' if bits[t] == bits[thread_counts[0]] else 'NO'} |")
                print(lines[-1], flush=True)
    text = (f"Medians of {repeats} runs, one and two threads alternating.\n\n"
            + "\n".join(lines) + "\n")
    with open(markdown, "w", encoding="utf-8") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
