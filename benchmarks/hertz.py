#!/usr/bin/env python3
"""Hertz contact (doc/validation.md): refinement study of prm/hertz.prm against the analytic solution.

    python3 benchmarks/hertz.py [--exe build/feticontact] [--n 12,16,24,32,40]
        [--markdown doc/reports/data/hertz.md] [--csv doc/reports/data/hertz_profile.csv] [--work DIR]
        [--prm prm/hertz_two_bodies.prm]
    /usr/bin/python3 benchmarks/hertz.py --plot doc/reports/data/hertz_profile.csv doc/reports/hertz_pressure.png
        [--prm prm/hertz_two_bodies.prm]

--prm prm/hertz_two_bodies.prm studies the two elastic bodies of that scene (mortar rows) instead
of the body on a rigid flat: 1/E* = 2 (1 − ν²)/E, the pressures of the indenter's nodes
(λ_N / D_kk).

The study is feticontact's own (`Refinement study/Subdivision factors` = n/16 with
Verification/Hertz of prm/hertz.prm): it solves the scene for every n (subdivisions per edge, the
grading kept) and writes a deal.II ConvergenceTable (convergence_table.org) with the measured
contact radius a and peak pressure p0, their errors against a = (3PR/(4E*))^(1/3) and
p0 = 3P/(2πa²), E* = E/(1 − ν²), and the rates log(e_{i−1}/e_i)/log(n_i/n_{i−1}). This script puts
that table into --markdown and checks it independently: from each cycle's contact.csv it measures
  - p0 and a: the weighted least-squares fit of p² = p0² − (p0²/a²) r² (linear in r²) over all
    pressed nodes (pressure above 1e-6 of the largest), each weighted by its lumped area, r the
    distance in the plane z = const from the node with the smallest initial gap;
  - the total contact force against the applied P (equilibrium, 4 × the quarter);
and requires a and p0 to agree with feticontact's to 1e-8 (contact.csv has 12 digits). The
measurement part uses the standard library only; --plot needs matplotlib.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

R, E, NU, P = 0.02, 2.1e11, 0.3, 5e3
L = 0.007            # edge of the quarter box (prm/hertz.prm)
GRADING = 6.0      # β of prm/hertz.prm
PRM = "prm/hertz.prm"
E_STAR = E / (1 - NU ** 2)
A = (3 * P * R / (4 * E_STAR)) ** (1 / 3)
P0 = 3 * P / (2 * math.pi * A ** 2)


def configure(prm):
    """The scene and its Hertz values: two elastic steel bodies for prm/hertz_two_bodies.prm."""
    global PRM, E_STAR, A, P0
    PRM = prm
    E_STAR = E / (1 - NU ** 2) / (2 if "two_bodies" in prm else 1)
    A = (3 * P * R / (4 * E_STAR)) ** (1 / 3)
    P0 = 3 * P / (2 * math.pi * A ** 2)


def read_contact(outdir):
    with open(os.path.join(outdir, "contact.csv")) as f:
        return [dict(zone=int(r["zone"]), r=math.hypot(float(r["x"]), float(r["y"])),
                     y=float(r["y"]), x=float(r["x"]), force=float(r["lambda_N"]),
                     p=float(r["pressure"]), area=float(r["area"]),
                     gap=float(r["weighted_gap"]) / float(r["D_kk"]))
                for r in csv.DictReader(f)]


def hertz_fit(rows):
    """p0, a and the number of nodes of the fit (see the module documentation)."""
    centre = min(rows, key=lambda r: r["gap"])
    p_max = max(r["p"] for r in rows)
    fit = [((r["x"] - centre["x"]) ** 2 + (r["y"] - centre["y"]) ** 2, r["p"] ** 2, r["area"])
           for r in rows if r["p"] > 1e-6 * p_max]
    # Normal equations of min Σ w (q − A + B s)², s = r², q = p².
    w = math.fsum(f[2] for f in fit)
    ws = math.fsum(f[2] * f[0] for f in fit)
    wss = math.fsum(f[2] * f[0] ** 2 for f in fit)
    wq = math.fsum(f[2] * f[1] for f in fit)
    wsq = math.fsum(f[2] * f[0] * f[1] for f in fit)
    det = w * wss - ws * ws
    A, B = (wss * wq - ws * wsq) / det, -(w * wsq - ws * wq) / det
    return math.sqrt(A), math.sqrt(A / B), len(fit)


def study():
    arguments(__doc__, ["--csv", "--exe", "--markdown", "--n", "--work", "--prm"], [])
    configure(option("--prm", PRM))
    exe = option("--exe", "build/feticontact")
    ns = [int(v) for v in option("--n", "12,16,24,32,40").split(",")]
    md_path = option("--markdown", "doc/reports/data/hertz.md")
    csv_path = option("--csv", "doc/reports/data/hertz_profile.csv")
    work = option("--work", tempfile.mkdtemp(prefix="hertz_"))
    factors = ", ".join(f"{n / 16:g}" for n in ns)
    command = [exe, "--set", f"Refinement study/Subdivision factors={factors}",
               "--set", f"Output/Directory={work}", "--set", "Output/Write vtu=false", PRM]
    run = subprocess.run(command, capture_output=True, text=True,
                         env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    if run.returncode != 0:
        raise SystemExit(f"feticontact failed ({run.returncode}):\n{run.stderr}")
    with open(os.path.join(work, "convergence_table.org")) as f:
        convergence_table = f.read()
    results, profiles = [], []
    for cycle, n in enumerate(ns, start=1):
        outdir = os.path.join(work, f"cycle-{cycle}")
        with open(os.path.join(outdir, "summary.json")) as f:
            summary = json.load(f)
        rows = [r for r in read_contact(outdir) if r["zone"] == 1]
        p0, a, n_fit = hertz_fit(rows)
        hertz = summary["hertz"]
        for key, mine in (("a", a), ("p0", p0), ("fit_nodes", n_fit)):
            if abs(mine - hertz[key]) > 1e-8 * abs(mine):
                raise SystemExit(f"n = {n}: {key} of feticontact {hertz[key]:.12e} differs from "
                                 f"this script's {mine:.12e}")
        h = L / n * GRADING / math.expm1(GRADING)  # the element at the contact point
        total = 4 * sum(r["force"] for r in rows)
        results.append(dict(n=n, h=h, dofs=summary["n_primal"], m=summary["m_contact"],
                            n_across=hertz["nodes_across_a"], n_fit=n_fit, a=a, p0=p0,
                            p0_touch=hertz["p0_touch_node"], total=total, time=summary["times"]["solve"],
                            n_A=summary["hessian_multiplications"]["total"]))
        profiles += [dict(n=n, r=r["r"], p=r["p"]) for r in rows if r["force"] > 0 or
                     r["r"] <= 1.5 * A]
        e = results[-1]
        print(f"n = {n}: a = {a:.5e} ({(a - A) / A:+.2%}), p0 = {e['p0']:.5e} "
              f"({(e['p0'] - P0) / P0:+.2%}; the touch node {(e['p0_touch'] - P0) / P0:+.2%}), "
              f"{e['n_fit']} nodes fitted, {e['n_across']} nodes across a, total force "
              f"{total:.6g} N, {e['time']:.2f} s", flush=True)
    os.makedirs(os.path.dirname(md_path), exist_ok=True)
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["n", "r", "p"])
        writer.writeheader()
        writer.writerows(profiles)
    text = table(results, convergence_table, " ".join(
        f'"{c}"' if " " in c else c for c in ["python3"] + sys.argv))
    with open(md_path, "w") as f:
        f.write(text)
    print(text)
    print(f"wrote {md_path} and {csv_path}")


def markdown_table(org):
    """deal.II's org-mode table with the header separator Markdown needs."""
    lines = [line.rstrip() for line in org.splitlines() if line.strip()]
    return "\n".join(lines[:1] + ["|" + "---|" * (lines[0].count("|") - 1)] + lines[1:])


def table(results, convergence_table, command):
    out = ["<!-- written by benchmarks/hertz.py -->", "",
           f"Command: `{command}` (feticontact's refinement study of {PRM}).", "",
           f"Hertz: a = {A:.5e} m (a/R = {A / R:.3f}), p0 = {P0:.5e} Pa, P = {P:g} N.", "",
           "deal.II ConvergenceTable written by feticontact (output/hertz/convergence_table.org;"
           " errors relative, rates log(e_{i−1}/e_i)/log(n_i/n_{i−1})):", "",
           markdown_table(convergence_table), "",
           "Signed errors, checked by this script from contact.csv (h: the element at the "
           "contact point):", "",
           "| n | unknowns | h at r = 0 (m) | nodes across a | nodes fitted | a error | p0 error "
           "| p0 error of the touch node | total contact force / P − 1 | time (s) | n_A |",
           "|---" * 11 + "|"]
    for i, r in enumerate(results):
        out.append(f"| {r['n']} | {r['dofs']} | {r['h']:.2e} | {r['n_across']} | {r['n_fit']} | "
                   f"{(r['a'] - A) / A:+.2%} | {(r['p0'] - P0) / P0:+.2%} | "
                   f"{(r['p0_touch'] - P0) / P0:+.2%} | "
                   f"{r['total'] / P - 1:.1e} | {r['time']:.2f} | {r['n_A']} |")
    return "\n".join(out) + "\n"


def plot(csv_path, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(csv_path) as f:
        rows = [dict(n=int(r["n"]), r=float(r["r"]), p=float(r["p"])) for r in csv.DictReader(f)]
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for n in sorted({r["n"] for r in rows}):
        pts = sorted((r["r"] / A, r["p"] / P0) for r in rows if r["n"] == n)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", ms=3, label=f"n = {n}")
    xs = [i / 200 for i in range(201)]
    ax.plot(xs, [math.sqrt(max(0, 1 - x * x)) for x in xs], "k-", lw=1.2,
            label="Hertz p0 √(1 − r²/a²)")
    ax.set_xlabel("r / a (Hertz)")
    ax.set_ylabel("λ_N / D_kk  /  p0 (Hertz)")
    ax.set_xlim(0, 1.5)
    ax.legend(fontsize=8)
    ax.set_title(f"Hertz: nodal pressure against radius ({os.path.basename(PRM)})")
    fig.tight_layout()
    fig.savefig(png_path, dpi=130)


if __name__ == "__main__":
    if "--prm" in sys.argv:
        configure(sys.argv[sys.argv.index("--prm") + 1])
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        plot(sys.argv[i + 1], sys.argv[i + 2])
    else:
        study()
