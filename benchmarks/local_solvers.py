#!/usr/bin/python3
"""Runs local_solver_benchmark for every local solver backend on the unit cube with
N = 6, 10, 14, 21, 31 cubes per edge (3(N+1)^3 = 1029 ... 98304 DoFs), once with OpenBLAS's
default number of threads and once with OPENBLAS_NUM_THREADS=1, and writes
doc/reports/data/local_solvers.csv and the plot doc/local_solvers.png (factorization time against DoFs).

A backend whose factorization took longer than --skip-after seconds (any repetition) at one size
is not run at the larger sizes of that thread setting; those rows have status 'skipped'.

The machine may be shared: before each run the script waits for the CPUs to be idle, measures
the CPU share used by other processes during the run (column other_cpu_share, from /proc/stat
minus the benchmark's own CPU time) and repeats a run disturbed by more than --max-other-share
(at most --attempts times; column attempts: the number of the attempt kept, the least
disturbed one). Rows still disturbed can be run again later with --rerun-disturbed.

Run with Debian's Python (numpy and matplotlib), after building the benchmark:
  cmake --build build --target local_solver_benchmark
  /usr/bin/python3 benchmarks/local_solvers.py
"""

import argparse
import csv
import os
import re
import resource
import subprocess
import sys
import time

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BACKENDS = ["cholmod", "amesos2-klu2", "amesos-mumps", "umfpack"]
FIELDS = ["openblas_threads", "backend", "n_cubes", "n_dofs", "nnz", "factorize_median_s",
          "solve_median_s", "factorize_max_s", "relative_residual", "load_average_1min",
          "other_cpu_share", "attempts", "status"]


def busy_cpu_seconds():
    """CPU time (s) spent by all processes of the machine, from /proc/stat."""
    with open("/proc/stat") as stat:
        user, nice, system, idle, iowait, irq, softirq, steal = map(
            int, stat.readline().split()[1:9])
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def wait_until_idle(max_busy, max_wait):
    """Waits (at most max_wait s) until the machine's busy CPU share over 5 s is below
    max_busy; returns whether it is."""
    start = time.monotonic()
    while True:
        busy0, wall0 = busy_cpu_seconds(), time.monotonic()
        time.sleep(5)
        share = (busy_cpu_seconds() - busy0) / ((time.monotonic() - wall0) * os.cpu_count())
        if share < max_busy:
            return True
        if time.monotonic() - start > max_wait:
            return False


def children_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_one(exe, backend, n_cubes, repeat, env, timeout):
    """Runs the benchmark once; returns the row fields (without thread setting)."""
    n_dofs = 3 * (n_cubes + 1) ** 3
    row = {"backend": backend, "n_cubes": n_cubes, "n_dofs": n_dofs,
           "load_average_1min": "%.2f" % os.getloadavg()[0]}
    busy0, own0, wall0 = busy_cpu_seconds(), children_cpu_seconds(), time.monotonic()
    try:
        p = subprocess.run([exe, "--backend", backend, "--cubes", str(n_cubes),
                            "--repeat", str(repeat)], env=env, capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        row["status"] = "failed: timeout after %d s" % timeout
        return row, None
    # The share of the machine's CPU capacity used by other processes during the run (0: the
    # machine was otherwise idle); a check that the timings were not disturbed.
    other = (busy_cpu_seconds() - busy0) - (children_cpu_seconds() - own0)
    row["other_cpu_share"] = "%.3f" % max(0.0, other / ((time.monotonic() - wall0) * os.cpu_count()))
    sys.stderr.write(p.stderr)
    lines = [l for l in p.stdout.splitlines() if l.strip()]
    if p.returncode != 0 or len(lines) != 1:
        row["status"] = "failed: exit status %d" % p.returncode
        return row, None
    name, dofs, nnz, t_f, t_s, residual = lines[0].split(",")
    assert name == backend and int(dofs) == n_dofs, lines[0]
    times = [float(t) for t in re.findall(r"factorize ([0-9.eE+-]+) s", p.stderr)]
    row.update(nnz=int(nnz), factorize_median_s=t_f, solve_median_s=t_s,
               factorize_max_s="%.6e" % max(times), relative_residual=residual,
               status="ok" if float(residual) < 1e-8 else "inaccurate")
    return row, max(times)


def run_undisturbed(args, backend, n_cubes, env):
    """run_one after waiting for an idle machine, repeated (at most --attempts times) while
    other processes used more than --max-other-share of the CPUs; keeps the least disturbed."""
    best = None
    for attempt in range(1, args.attempts + 1):
        wait_until_idle(args.max_other_share, args.max_wait)
        row, t_max = run_one(args.exe, backend, n_cubes, args.repeat, env, args.timeout)
        row["attempts"] = attempt
        if t_max is None:
            return row, t_max
        if best is None or float(row["other_cpu_share"]) < float(best[0]["other_cpu_share"]):
            best = (row, t_max)
        if float(row["other_cpu_share"]) <= args.max_other_share:
            break
        print("# %s, %d DoFs: other processes used %s of the CPUs, attempt %d"
              % (backend, row["n_dofs"], row["other_cpu_share"], attempt), file=sys.stderr)
    return best


def plot(rows, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    settings = list(dict.fromkeys(r["openblas_threads"] for r in rows))
    fig, axes = plt.subplots(1, len(settings), figsize=(6 * len(settings), 4.8), sharey=True,
                             squeeze=False)
    for ax, setting in zip(axes[0], settings):
        for i, backend in enumerate(BACKENDS):
            pts = [(int(r["n_dofs"]), float(r["factorize_median_s"])) for r in rows
                   if r["openblas_threads"] == setting and r["backend"] == backend
                   and r["status"] == "ok"]
            if pts:
                ax.loglog(*zip(*pts), marker="os^D"[i], label=backend)
        ax.set_title("OPENBLAS_NUM_THREADS=%s" % setting if setting != "default"
                     else "OpenBLAS default threads (%d cores)" % os.cpu_count())
        ax.set_xlabel("DoFs (3(N+1)$^3$)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    axes[0][0].set_ylabel("factorization time, median of repetitions (s)")
    fig.suptitle("Local solver backends: P1 elasticity on the unit cube, one subdomain")
    fig.tight_layout()
    fig.savefig(filename, dpi=120)


def markdown(rows):
    """Prints one table per thread setting (times in seconds)."""
    for setting in dict.fromkeys(r["openblas_threads"] for r in rows):
        sub = [r for r in rows if r["openblas_threads"] == setting]
        backends = list(dict.fromkeys(r["backend"] for r in sub))
        print("\nOPENBLAS_NUM_THREADS=%s\n" % setting)
        print("| DoFs | nnz | " + " | ".join("%s factorize / solve" % b for b in backends)
              + " |")
        print("|---:|---:|" + "---:|" * len(backends))
        for n in dict.fromkeys(r["n_dofs"] for r in sub):
            cells, nnz = [], ""
            for b in backends:
                r = next(r for r in sub if r["n_dofs"] == n and r["backend"] == b)
                nnz = r.get("nnz") or nnz
                cells.append("%.3g / %.3g" % (float(r["factorize_median_s"]),
                                              float(r["solve_median_s"]))
                             if r["status"] == "ok" else r["status"])
            print("| %s | %s | %s |" % (n, nnz, " | ".join(cells)))


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--exe", default=os.path.join(SOURCE, "build", "benchmarks",
                                                      "local_solver_benchmark"))
    parser.add_argument("--cubes", default="6,10,14,21,31")
    parser.add_argument("--backends", default=",".join(BACKENDS))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", default="default,1",
                        help="OpenBLAS thread settings: 'default' (variable unset) or a number")
    parser.add_argument("--skip-after", type=float, default=30.0)
    parser.add_argument("--timeout", type=int, default=1800)
    parser.add_argument("--max-other-share", type=float, default=0.15,
                        help="a run during which other processes used more of the CPUs "
                        "is repeated (the busy share of an idle machine is < 0.1)")
    parser.add_argument("--attempts", type=int, default=4)
    parser.add_argument("--rerun-disturbed", action="store_true",
                        help="only run again the rows of --csv with other_cpu_share above "
                        "--max-other-share (all other options as in the first run)")
    parser.add_argument("--max-wait", type=float, default=1200,
                        help="longest wait (s) for an idle machine before a run")
    parser.add_argument("--csv", default=os.path.join(SOURCE, "doc", "reports", "data", "local_solvers.csv"))
    parser.add_argument("--png", default=os.path.join(SOURCE, "doc", "local_solvers.png"))
    args = parser.parse_args()

    if args.rerun_disturbed:
        return rerun_disturbed(args)
    cubes = [int(n) for n in args.cubes.split(",")]
    backends = args.backends.split(",")
    rows = []
    for setting in args.threads.split(","):
        env = thread_env(setting)
        too_slow = {}  # backend -> why it is skipped at the larger sizes
        for n in cubes:
            for backend in backends:
                if backend in too_slow:
                    rows.append({"openblas_threads": setting, "backend": backend, "n_cubes": n,
                                 "n_dofs": 3 * (n + 1) ** 3,
                                 "status": too_slow[backend]})
                    continue
                row, t_max = run_undisturbed(args, backend, n, env)
                row["openblas_threads"] = setting
                rows.append(row)
                print(",".join(str(row.get(f, "")) for f in FIELDS), flush=True)
                if t_max is None:
                    too_slow[backend] = "skipped (failed at %d DoFs)" % row["n_dofs"]
                elif t_max > args.skip_after:
                    too_slow[backend] = ("skipped (a factorization took %.0f s > %g s at %d DoFs)"
                                         % (t_max, args.skip_after, row["n_dofs"]))

    return write_results(args, rows)


def thread_env(setting):
    env = dict(os.environ)
    env.pop("OPENBLAS_NUM_THREADS", None)
    if setting != "default":
        env["OPENBLAS_NUM_THREADS"] = setting
    return env


def write_results(args, rows):
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=FIELDS)
        writer.writeheader()
        for r in rows:
            writer.writerow({f: r.get(f, "") for f in FIELDS})
    plot(rows, args.png)
    markdown(rows)
    return 0 if all(r["status"] == "ok" or r["status"].startswith("skipped") for r in rows) else 1


def rerun_disturbed(args):
    """Runs again the rows of --csv whose other_cpu_share exceeds --max-other-share and keeps
    the new result where it was less disturbed; rewrites the CSV and the plot."""
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    for i, r in enumerate(rows):
        if r["status"] != "ok" or float(r["other_cpu_share"]) <= args.max_other_share:
            continue
        new, _ = run_undisturbed(args, r["backend"], int(r["n_cubes"]),
                                 thread_env(r["openblas_threads"]))
        new = {k: str(v) for k, v in new.items()}
        new["openblas_threads"] = r["openblas_threads"]
        print(",".join(new.get(f, "") for f in FIELDS), flush=True)
        if new["status"] == "ok" and float(new["other_cpu_share"]) < float(r["other_cpu_share"]):
            rows[i] = new
    return write_results(args, rows)


if __name__ == "__main__":
    sys.exit(main())
