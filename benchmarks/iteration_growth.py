#!/usr/bin/env python3
"""How the iteration counts grow with the number of subdomains at fixed H/h, from the linear
problem to Coulomb friction.

Brick of doc/formulation.md ("The brick benchmark") with subdomains of 8 x 8 x 8 cubes (H/h = 8, TFETI), k = 8a cubes across,
3a x a x a subdomains. For each a, on the same decomposition:

  - linear: prm/brick.prm (no contact), projected CG to the default relative tolerance 1e-10,
    `FETI/Preconditioner = none | lumped`: iterations (one application of F each);
  - contact: prm/kucera_table_2.prm with `Contact solver/Algorithm = mpgp` and the values that
    `auto` gives for it in `Contact solver` (subsections Expert, MPGP, SMALBE) (projected cg expansion, Hessian norm bound
    max, Inexact MSA factor 0.001, Recursive gradient tolerance 0.1, Arc preconditioner scale
    mean diagonal, the penalty factor 5 or --penalty-factor), that is the solver's defaults, for
    each friction coefficient μ: n_A (Hessian multiplications), SMALBE and MSA iterations, MPGP steps.

μ = 0 is the frictionless problem (one bound-constrained QP), the Coulomb problem without its
fixed point. The counts do not depend on the machine's speed, so runs may share the cores
(--jobs 2); the times in the CSV are then those of a shared machine and are not reported.

Usage: iteration_growth.py [--exe PATH] [--a 1,2,3,4,6] [--friction 0,0.3] [--jobs 1]
       [--penalty-factor 3]
       [--csv doc/reports/data/iteration_growth.csv] [--markdown doc/reports/data/iteration_growth.md]
       iteration_growth.py --plot doc/reports/data/iteration_growth.csv doc/reports/iteration_growth.png
(the plot needs matplotlib: /usr/bin/python3 on Debian with python3-matplotlib)

The executable is copied to a temporary file first, so that a rebuild during the run does not
change it. OPENBLAS_NUM_THREADS=1.
"""
import concurrent.futures
import csv
import os
import shutil
import subprocess
import sys
import tempfile

from cli import arguments, option
from lumped_preconditioner import row as lumped_row
from scaling import env, read_summary, settings

HERE = os.path.dirname(os.path.abspath(__file__))
PRM = os.path.join(HERE, "..", "prm")
# The MPGP, SMALBE and Expert values of the defaults (the penalty norm field of scaling.settings is unused);
# the penalty factor is the program's default unless --penalty-factor is given.
MPGP_DEFAULTS = ("projected cg", "max", "0.001", "0.1", "mean diagonal", "", "", "")
FIELDS = ["problem", "F", "a", "k", "n_subdomains", "n", "m", "preconditioner", "iterations",
          "n_A", "smalbe", "msa", "cg", "expansion", "proportioning", "converged"]


def run(exe, prm, sets):
    with tempfile.TemporaryDirectory() as out:
        command = [exe, *sets, "--set", f"Output/Directory={out}", prm]
        p = subprocess.run(command, capture_output=True, text=True, env=env())
        return read_summary(p, command, out)


def linear(exe, a, preconditioner):
    k = 8 * a
    sets = ["--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
            "--set", "Body 1/Decomposition/Method=blocks",
            "--set", f"Body 1/Decomposition/Blocks={3 * a}, {a}, {a}",
            "--set", "FETI/Dirichlet treatment=total",
            "--set", f"FETI/Preconditioner={preconditioner}",
            "--set", "Verification/Compare with monolithic solve=false",
            "--set", "Output/Write vtu=false", "--set", "Output/Write displacement csv=false"]
    s = run(exe, os.path.join(PRM, "brick.prm"), sets)
    return row("linear", "", a, k, preconditioner, s)


def contact(exe, a, friction):
    k = 8 * a
    sets = settings(k, (3 * a, a, a), MPGP_DEFAULTS[:6] + (option("--penalty-factor", ""), ""))
    sets = [s if not s.startswith("Contact/Zone 1/Friction coefficient=")
            else f"Contact/Zone 1/Friction coefficient={friction}" for s in sets]
    s = run(exe, os.path.join(PRM, "kucera_table_2.prm"), sets)
    return row("contact", friction, a, k, "none", s)


def row(problem, friction, a, k, preconditioner, s):
    r = lumped_row(problem, friction, a, k, preconditioner, s)
    r["msa"] = s.get("outer_iterations", "") if problem == "contact" else ""
    return r


def ratio(values):
    first = values[0]
    return f"{values[-1] / first:.2f}" if first else ""


def write_markdown(path, rows, a_list, frictions, command):
    def find(problem, a, key_name, key_value):
        for r in rows:
            if r["problem"] == problem and r["a"] == a and str(r[key_name]) == str(key_value):
                return r
        return None

    with open(path, "w") as f:
        f.write("<!-- written by benchmarks/iteration_growth.py -->\n\n"
                "# Growth of the iteration counts at fixed H/h\n\n"
                f"Written by `{command}`. H/h = 8, TFETI, k cubes across the brick's width, "
                "3a × a × a subdomains, one run per cell. Linear: projected CG iterations to "
                "‖P(Fλ − h)‖ ≤ 1e-10 ‖Ph‖ (one application of F each). Contact: n_A with the "
                "solver's defaults" + (f" but penalty factor {option('--penalty-factor', '')}"
                                       if option("--penalty-factor", "") else "") +
                ", SMALBE and MSA iterations in parentheses; "
                "μ = 0 is the frictionless problem.\n\n")
        header = ["k", "subdomains", "n", "linear, none", "linear, lumped"]
        header += [f"n_A, μ = {fr} (SMALBE, MSA)" for fr in frictions]
        header += [f"n_A / linear none, μ = {fr}" for fr in frictions]
        f.write("| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n")
        columns = {h: [] for h in header}
        for a in a_list:
            none, lumped = find("linear", a, "preconditioner", "none"), \
                find("linear", a, "preconditioner", "lumped")
            base = none or lumped or next((r for r in rows if r["a"] == a), None)
            if base is None:
                continue
            cells = [str(base["k"]), str(base["n_subdomains"]), f"{base['n']:,}",
                     str(none["iterations"]) if none else "",
                     str(lumped["iterations"]) if lumped else ""]
            columns["linear, none"].append(none["iterations"] if none else 0)
            columns["linear, lumped"].append(lumped["iterations"] if lumped else 0)
            for fr in frictions:
                r = find("contact", a, "F", fr)
                cells.append(f"{r['n_A']} ({r['smalbe']}, {r['msa']})" if r else "")
                columns[f"n_A, μ = {fr} (SMALBE, MSA)"].append(r["n_A"] if r else 0)
            for fr in frictions:
                r = find("contact", a, "F", fr)
                cells.append(f"{r['n_A'] / none['iterations']:.1f}" if r and none else "")
            f.write("| " + " | ".join(cells) + " |\n")
        f.write("| largest / smallest | | | " +
                " | ".join(ratio(columns[h]) for h in header[3:5 + len(frictions)]) +
                " |" + " |" * len(frictions) + "\n")


def plot(csv_path, png_path):
    """Every count divided by its value on the smallest decomposition, against n, with the band
    of goal 2 (1.5x)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    series = [("linear", "", "none", "iterations", "linear FETI, no preconditioner", "o"),
              ("linear", "", "lumped", "iterations", "linear FETI, lumped preconditioner", "s")]
    series += [("contact", fr, "none", "n_A", f"contact, μ = {fr}: n_A", m)
               for fr, m in zip(sorted({r["F"] for r in rows if r["problem"] == "contact"}),
                                "^v*D")]
    for problem, friction, preconditioner, column, label, marker in series:
        sel = sorted([r for r in rows if r["problem"] == problem and r["F"] == friction
                      and r["preconditioner"] == preconditioner], key=lambda r: int(r["n"]))
        if sel:
            first = float(sel[0][column])
            ax.semilogx([int(r["n"]) for r in sel], [float(r[column]) / first for r in sel],
                        marker=marker, label=label)
    ax.axhline(1.5, color="k", linestyle="--", label="goal 2: 1.5 × the smallest")
    ax.set_xlabel("primal unknowns n (H/h = 8, 3 … 648 subdomains)")
    ax.set_ylabel("count / count on the smallest decomposition")
    ax.set_ylim(bottom=0.9)
    ax.legend(fontsize="small")
    ax.set_title("Growth of the iteration counts at fixed H/h")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


def main():
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        if len(sys.argv) != 4 or i != 1:
            raise SystemExit("usage: iteration_growth.py --plot CSV PNG (see --help)")
        plot(sys.argv[2], sys.argv[3])
        return
    arguments(__doc__, ["--exe", "--a", "--friction", "--jobs", "--csv", "--markdown",
                        "--penalty-factor"])
    exe_source = option("--exe", os.path.join(HERE, "..", "build", "feticontact"))
    a_list = [int(x) for x in option("--a", "1,2,3,4,6").split(",") if x]
    frictions = [x for x in option("--friction", "0,0.3").split(",") if x]
    jobs = int(option("--jobs", "1"))
    csv_path = option("--csv", os.path.join(HERE, "..", "doc", "reports", "data", "iteration_growth.csv"))
    markdown = option("--markdown", os.path.join(HERE, "..", "doc", "reports", "data",
                                                 "iteration_growth.md"))
    command = "python3 benchmarks/iteration_growth.py " + " ".join(sys.argv[1:])
    with tempfile.TemporaryDirectory() as tmp:
        exe = os.path.join(tmp, "feticontact")
        shutil.copy2(exe_source, exe)
        # Largest problems first, so that two jobs finish close together.
        tasks = []
        for a in sorted(a_list, reverse=True):
            tasks += [(contact, a, fr) for fr in reversed(frictions)]
            tasks += [(linear, a, pc) for pc in ("none", "lumped")]
        rows, failures = [], []
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = [pool.submit(fn, exe, a, arg) for fn, a, arg in tasks]
            for future in concurrent.futures.as_completed(futures):
                # A failed run is reported and the others go on (a run at 10⁶ unknowns takes
                # a quarter of an hour); the tables are written from the runs that succeeded.
                try:
                    rows.append(future.result())
                except SystemExit as failure:
                    failures.append(str(failure))
                    print(failure, file=sys.stderr, flush=True)
                    continue
                print(rows[-1], flush=True)
                save(csv_path, rows)
    save(csv_path, rows)
    write_markdown(markdown, rows, a_list, frictions, command)
    if failures:
        raise SystemExit(f"{len(failures)} run(s) failed; the tables hold the others")


def save(path, rows):
    rows.sort(key=lambda r: (r["problem"], str(r["F"]), r["a"], r["preconditioner"]))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
