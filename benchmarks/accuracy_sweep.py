#!/usr/bin/env python3
"""Speed against accuracy on the paper's brick (doc/formulation.md, "The brick benchmark"; μ = 0.3): the solver tolerances
swept from loose to tight, each run compared with a reference solve of the same mesh at 1e-12,
and the discretization error of each mesh against the finest, so that a user sees the tolerance
below which solving harder buys nothing.

    python3 benchmarks/accuracy_sweep.py [--exe build/feticontact] [--k 8,16,24]
        [--tolerances 1e-2,1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10] [--repeats 3]
        [--repeats-large 1] [--algorithm mpgp] [--reference-tolerance 1e-12] [--timeout 7200]
        [--csv doc/reports/data/accuracy_sweep.csv] [--markdown doc/reports/data/accuracy_sweep.md]
        [--work DIR] [--keep-measured] [--add-repeats N]
    /usr/bin/python3 benchmarks/accuracy_sweep.py --plot doc/reports/data/accuracy_sweep.csv doc/reports/accuracy_sweep.png

One tolerance t sets both relative tolerances, `MSA relative tolerance = t` and `QP relative
tolerance = t` (doc/formulation.md, "Relative tolerances"). For each k and t:
  time      median wall time of --repeats runs (k ≥ 16: --repeats-large) without output,
            i.e. setup + assembly + factorization + coarse problem + solve + primal recovery;
  Iter, n_A the MSA steps and Hessian multiplications;
  e_max     max_v |u − u_ref| / max_v |u_ref| against the reference solve (QP = MSA = 1e-12);
  e_energy  ‖u − u_ref‖_K / ‖u_ref‖_K (feticontact's Verification/Reference displacements);
  e_force   ‖λ − λ_ref‖ / ‖λ_ref‖ over the contact forces (λ_N, λ_T1, λ_T2 of every node);
  status    the number of contact nodes whose open/stick/slip status differs from the reference.
The discretization error of mesh k is that of its reference solve against the finest mesh's,
max_v |u_k − u_fine| / max_v |u_fine| over the vertices of the coarsest mesh (they belong to
every mesh when the coarsest k divides every other k, as 8 | 16 and 8 | 24).
--add-repeats N runs the measured rows of the meshes --k again until each has N runs (for the
rows measured once; the medians then cover all runs, and each repeat must reproduce n_A).
--keep-measured keeps the rows already in --csv and runs only the missing (k, tolerance) pairs;
the reference solves are taken from --work (reference_k<k>/) when there, else solved again (they
are needed for the errors and the discretization error).
The measurement uses the standard library only; --plot needs matplotlib.
"""
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

from cli import arguments, option

PRM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "prm", "kucera_table_2.prm")
FIELDS = ["k", "n", "tolerance", "status", "time", "time_solve", "iter", "n_A", "e_max",
          "e_energy", "e_force", "status_changes", "runs"]
# The single runs behind the medians (';'-separated), so that --add-repeats can add runs later.
RAW = ["times", "solve_times"]


def run(exe, k, tolerance, algorithm, outdir, timeout, reference=None):
    settings = ["--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
                "--set", f"Contact solver/Algorithm={algorithm}",
                "--set", f"Contact solver/MSA relative tolerance={tolerance}",
                "--set", f"Contact solver/QP relative tolerance={tolerance}",
                "--set", "Output/Write vtu=false",
                "--set", "Output/Write displacement csv=true",
                "--set", f"Output/Directory={outdir}"]
    if reference:
        settings += ["--set", f"Verification/Reference displacements={reference}"]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    try:
        p = subprocess.run([exe, *settings, PRM], capture_output=True, text=True,
                           timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None, "timeout"
    path = os.path.join(outdir, "summary.json")
    if not os.path.exists(path):
        sys.stderr.write(p.stderr)
        return None, f"exit {p.returncode}"
    with open(path) as f:
        summary = json.load(f)
    return summary, "converged" if summary["converged"] else f"not converged (exit {p.returncode})"


def read_contact(directory):
    with open(os.path.join(directory, "contact.csv")) as f:
        return {(r["zone"], round(float(r["x"]), 9), round(float(r["y"]), 9), round(float(r["z"]), 9)):
                r for r in csv.DictReader(f)}


def contact_errors(directory, reference):
    ours = read_contact(directory)
    diff2 = norm2 = 0.0
    changes = 0
    for key, r in reference.items():
        o = ours[key]
        for c in ("lambda_N", "lambda_T1", "lambda_T2"):
            diff2 += (float(o[c]) - float(r[c])) ** 2
            norm2 += float(r[c]) ** 2
        changes += o["status"] != r["status"]
    return math.sqrt(diff2 / norm2) if norm2 > 0 else math.sqrt(diff2), changes


def read_displacements(directory):
    with open(os.path.join(directory, "displacements.csv")) as f:
        return {(round(float(r["x"]), 9), round(float(r["y"]), 9), round(float(r["z"]), 9)):
                [float(r[c]) for c in ("ux", "uy", "uz")] for r in csv.DictReader(f)}


def time_without_output(summary):
    t = summary["times"]
    return t["total"] - t.get("output", 0.0)


def reference_row(summary, k, reference_tolerance, status):
    return dict(k=k, n=summary["n_primal"], tolerance=reference_tolerance, status=status,
                time=time_without_output(summary), time_solve=summary["times"]["solve"],
                iter=summary["outer_iterations"],
                n_A=summary["hessian_multiplications"]["total"], e_max=0.0, e_energy=0.0,
                e_force=0.0, status_changes=0, runs=1)


def measure(exe, ks, tolerances, repeats, repeats_large, algorithm, reference_tolerance, timeout,
            keep, save, measured=()):
    """Runs the sweep; save(rows, discretization) after every row (a long sweep that is cut
    short keeps what it measured). Rows in `measured` are kept: only the (k, tolerance) pairs
    missing from them are run, and a reference solve only when --work does not hold it."""
    rows, discretization = [], {}
    references = {}
    for k in ks:
        ref_dir = os.path.join(keep, f"reference_k{k}")
        references[k] = ref_dir
        old = {r["tolerance"]: r for r in measured if r["k"] == k and r.get("runs")}
        if os.path.exists(os.path.join(ref_dir, "displacements.csv")) and old:
            print(f"k = {k}: reference solve kept", flush=True)
        else:
            summary, status = run(exe, k, reference_tolerance, algorithm, ref_dir, timeout)
            print(f"k = {k}: reference at {reference_tolerance:g}: {status}", flush=True)
            if summary is None or not summary["converged"]:
                raise SystemExit(f"the reference solve at k = {k} failed: {status}")
            old[reference_tolerance] = reference_row(summary, k, reference_tolerance, status)
        rows.append(old[reference_tolerance])
        reference_contact = read_contact(ref_dir)
        for t in tolerances:
            if t in old:
                rows.append(old[t])
                continue
            times, solve_times, summary, status = [], [], None, ""
            n_runs = repeats if k < 16 else repeats_large
            with tempfile.TemporaryDirectory() as out:
                for _ in range(n_runs):
                    summary, status = run(exe, k, t, algorithm, out, timeout,
                                          os.path.join(ref_dir, "displacements.csv"))
                    if summary is None:
                        break
                    times.append(time_without_output(summary))
                    solve_times.append(summary["times"]["solve"])
                if summary is None:
                    rows.append(dict(k=k, tolerance=t, status=status, runs=0))
                    print(f"k = {k}, t = {t:g}: {status}", flush=True)
                    continue
                e_force, changes = contact_errors(out, reference_contact)
            d = summary["reference_difference"]
            row = dict(k=k, n=summary["n_primal"], tolerance=t, status=status,
                       times=times, solve_times=solve_times,
                       time=statistics.median(times), time_solve=statistics.median(solve_times),
                       iter=summary["outer_iterations"],
                       n_A=summary["hessian_multiplications"]["total"],
                       e_max=d["max_relative"], e_energy=d["energy_relative"], e_force=e_force,
                       status_changes=changes, runs=len(times))
            rows.append(row)
            save(rows, discretization)
            print(", ".join(f"{key} = {row[key]}" for key in FIELDS if key in row), flush=True)
    # Discretization error: each reference against the finest, on the coarsest mesh's vertices.
    fine = read_displacements(references[ks[-1]])
    coarse_nodes = read_displacements(references[ks[0]]).keys()
    scale = max(max(abs(c) for c in fine[p]) for p in coarse_nodes)
    for k in ks[:-1]:
        u = read_displacements(references[k])
        discretization[k] = max(max(abs(a - b) for a, b in zip(u[p], fine[p]))
                                for p in coarse_nodes) / scale
    return rows, discretization


def add_repeats(exe, rows, ks, target, algorithm, timeout, save, discretization):
    """More runs for the measured rows of the meshes ks that have fewer than target runs (their
    single runs known): the medians are taken over all runs, and every new run must repeat the
    stored multiplication count (the solver is deterministic)."""
    for row in rows:
        if row["k"] not in ks or row["status"] != "converged" or row.get("e_max") == 0.0:
            continue
        missing = target - row["runs"]
        if missing <= 0:
            continue
        if len(row["times"]) != row["runs"]:
            print(f"k = {row['k']}, t = {row['tolerance']:g}: single runs unknown, skipped")
            continue
        for _ in range(missing):
            with tempfile.TemporaryDirectory() as out:
                summary, status = run(exe, row["k"], row["tolerance"], algorithm, out, timeout)
            if summary is None or summary["hessian_multiplications"]["total"] != row["n_A"]:
                raise SystemExit(f"k = {row['k']}, t = {row['tolerance']:g}: the repeat gave "
                                 f"{status}, n_A {summary and summary['hessian_multiplications']}"
                                 f" against {row['n_A']}")
            row["times"].append(time_without_output(summary))
            row["solve_times"].append(summary["times"]["solve"])
        row["runs"] = len(row["times"])
        row["time"] = statistics.median(row["times"])
        row["time_solve"] = statistics.median(row["solve_times"])
        save(rows, discretization)
        print(f"k = {row['k']}, t = {row['tolerance']:g}: {row['runs']} runs, median "
              f"{row['time']:.3g} s ({', '.join(f'{v:.3g}' for v in row['times'])})", flush=True)


def write_csv(path, rows, discretization):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS + ["discretization_error"] + RAW)
        w.writeheader()
        for r in rows:
            raw = {key: ";".join(repr(v) for v in r.get(key, [])) for key in RAW}
            w.writerow({**{key: r.get(key, "") for key in FIELDS},
                        "discretization_error": discretization.get(r["k"], ""), **raw})


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    discretization = {}
    for r in rows:
        for key in ("k", "n", "iter", "n_A", "status_changes", "runs"):
            if r.get(key):
                r[key] = int(float(r[key]))
        for key in ("tolerance", "time", "time_solve", "e_max", "e_energy", "e_force"):
            if r.get(key):
                r[key] = float(r[key])
        if r.get("discretization_error"):
            discretization[r["k"]] = float(r["discretization_error"])
        for key in RAW:
            r[key] = [float(v) for v in r[key].split(";")] if r.get(key) else []
        # Rows written before the raw columns: a single run is its own median.
        if r.get("runs") == 1 and not r["times"]:
            r["times"], r["solve_times"] = [r["time"]], [r["time_solve"]]
    return rows, discretization


def write_markdown(path, rows, discretization, command):
    out = ["<!-- written by benchmarks/accuracy_sweep.py -->", "",
           f"Command: `{command}`", "",
           "| k | n | tolerance | time [s] | solve [s] | Iter | n_A | e_max | e_energy | e_force "
           "| status changes | runs |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r.get("runs", 0) == 0:
            out.append(f"| {r['k']} | | {r['tolerance']:g} | {r['status']} | | | | | | | | |")
            continue
        ref = r["tolerance"] <= 1e-12
        out.append(
            f"| {r['k']} | {r['n']} | {r['tolerance']:g}{' (reference)' if ref else ''} | "
            f"{r['time']:.3g} | {r['time_solve']:.3g} | {r['iter']} | {r['n_A']} | "
            + (" — | — | — | — |" if ref else
               f"{r['e_max']:.1e} | {r['e_energy']:.1e} | {r['e_force']:.1e} | {r['status_changes']} |")
            + f" {r['runs']} |")
    out += ["", "Discretization error (reference solve of mesh k against the finest mesh, max over "
            "the vertices of the coarsest mesh):", ""]
    for k, e in sorted(discretization.items()):
        out.append(f"- k = {k}: {e:.2e}")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def plot(csv_path, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows, discretization = read_csv(csv_path)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for k in sorted({r["k"] for r in rows}):
        sweep = sorted((r for r in rows if r["k"] == k and r.get("runs", 0) > 0
                        and r["tolerance"] > 1e-12), key=lambda r: r["time"])
        if not sweep:
            continue
        times = [r["time"] for r in sweep]
        line, = axes[0].loglog(times, [r["e_energy"] for r in sweep], "o-", label=f"k = {k}")
        axes[1].loglog([r["tolerance"] for r in sweep], [r["e_energy"] for r in sweep], "o-",
                       color=line.get_color(), label=f"k = {k}")
        if k in discretization:
            for ax in axes:
                ax.axhline(discretization[k], color=line.get_color(), ls=":", lw=1)
    axes[0].set_xlabel("wall time without output [s]")
    axes[0].set_ylabel("‖u − u_ref‖_K / ‖u_ref‖_K (solver error)")
    axes[0].set_title("Error against time (dotted: discretization error)")
    axes[1].set_xlabel("relative tolerance t (MSA = QP = t)")
    axes[1].set_ylabel("solver error in the energy norm")
    axes[1].set_title("Error against tolerance")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


def main():
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        plot(sys.argv[i + 1], sys.argv[i + 2])
        return
    arguments(__doc__, ["--add-repeats", "--algorithm", "--csv", "--exe", "--k", "--markdown",
              "--reference-tolerance", "--repeats", "--repeats-large", "--timeout",
              "--tolerances", "--work"], ["--keep-measured"])
    exe = option("--exe", "build/feticontact")
    ks = [int(v) for v in option("--k", "8,16,24").split(",")]
    tolerances = [float(v) for v in
                  option("--tolerances", "1e-2,1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10").split(",")]
    repeats = int(option("--repeats", "3"))
    repeats_large = int(option("--repeats-large", "1"))
    algorithm = option("--algorithm", "mpgp")
    reference_tolerance = float(option("--reference-tolerance", "1e-12"))
    timeout = float(option("--timeout", "7200"))
    csv_path = option("--csv", "doc/reports/data/accuracy_sweep.csv")
    md_path = option("--markdown", "doc/reports/data/accuracy_sweep.md")
    keep = option("--work", tempfile.mkdtemp(prefix="accuracy_sweep_"))
    command = "python3 " + " ".join(sys.argv)

    def save(rows, discretization):
        write_csv(csv_path, rows, discretization)
        write_markdown(md_path, rows, discretization, command)

    if "--add-repeats" in sys.argv:
        rows, discretization = read_csv(csv_path)
        if os.path.exists(md_path):
            with open(md_path) as f:
                first = [line for line in f if line.startswith("Command: `")]
            if first:
                command = first[0][len("Command: `"):].rstrip().rstrip("`") + "`, then `" + command
        add_repeats(exe, rows, ks, int(option("--add-repeats", "3")), algorithm, timeout, save,
                    discretization)
        return
    measured = read_csv(csv_path)[0] if "--keep-measured" in sys.argv else []
    rows, discretization = measure(exe, ks, tolerances, repeats, repeats_large, algorithm,
                                   reference_tolerance, timeout, keep, save, measured)
    save(rows, discretization)
    print(f"wrote {csv_path}, {md_path}")


if __name__ == "__main__":
    main()
