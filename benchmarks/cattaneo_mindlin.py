#!/usr/bin/env python3
"""Cattaneo–Mindlin (doc/validation.md): the stick radius of prm/cattaneo_mindlin.prm against
c = a (1 − Q/(μP))^(1/3), and full sliding for Q > μP.

    python3 benchmarks/cattaneo_mindlin.py [--exe build/feticontact] [--n 16]
        [--ratios 0,0.2,0.4,0.6,0.8,0.9] [--sliding 1.2] [--poisson 0.3]
        [--markdown doc/reports/data/cattaneo_mindlin.md] [--csv doc/reports/data/cattaneo_mindlin.csv]
        [--prm prm/cattaneo_mindlin_pair.prm]
    /usr/bin/python3 benchmarks/cattaneo_mindlin.py --plot doc/reports/data/cattaneo_mindlin.csv \\
        doc/reports/cattaneo_mindlin.png

--prm prm/cattaneo_mindlin_pair.prm: the indenter on an elastic steel block (mortar rows) instead
of the rigid flat; the block's subdivisions are 5/4 of the indenter's, both bodies get --poisson,
and 1/E* = 2 (1 − ν²)/E.

The half indenter is held by its top face (moved down by δ, prm/cattaneo_mindlin.prm), so P is
the reaction: a first run with Q = 0 gives P, and then Q = q μ P is applied for every ratio q
of --ratios as the traction Q / (4 L²) on the top face (L = 7 mm). Each run's contact.csv gives
(the half model's sums doubled):
  P, Q      the total normal and tangential (x) contact forces (q_meas = Q / (μP));
  a_meas    √(A_contact / π), A_contact the lumped area of the nodes in contact (stick or slip);
  c_meas    √(A_stick / π), A_stick that of the sticking nodes;
  x_stick   the area-weighted mean x of the sticking nodes over a_meas (the stick zone's shift);
  slip_Q0   for q = 0: the slipping nodes already there (Spence: a deformable sphere on a rigid
            flat slips inwards near the edge under the normal load alone).
c_meas / a_meas is compared with (1 − q_meas)^(1/3); a_meas with the Hertz a = (3PR/(4E*))^(1/3)
of the measured P. For --sliding q > 1 the run must stop with exit status 4 and "no equilibrium".
--poisson ν changes Poisson's ratio (the coupling of normal and tangential tractions of an
elastic sphere on a rigid flat is measured by Dundurs' β = (1 − 2ν)/(2(1 − ν)), 0 at ν = 0.5).
The measurement part uses the standard library only; --plot needs matplotlib.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

R, E, MU, L = 0.02, 2.1e11, 0.3, 0.007
NU = float(sys.argv[sys.argv.index("--poisson") + 1]) if "--poisson" in sys.argv else 0.3
PRM = (sys.argv[sys.argv.index("--prm") + 1] if "--prm" in sys.argv else
       os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "prm", "cattaneo_mindlin.prm"))
PAIR = "pair" in os.path.basename(PRM)
E_STAR = E / (1 - NU ** 2) / (2 if PAIR else 1)
FIELDS = ["n", "nu", "q", "q_meas", "P", "Q", "a_hertz", "a_meas", "c_meas", "c_over_a", "c_theory",
          "x_stick", "stick", "slip", "n_A", "time", "status"]


def solve(exe, n, traction_x, outdir):
    cmd = [exe, "--set", f"Body 1/Mesh/Subdivisions={2 * n}, {n}, {n}",
           "--set", f"Body 1/Boundary conditions/Tractions=5: {traction_x!r}, 0, 0",
           "--set", f"Body 1/Material/Poisson's ratio={NU}",
           "--set", f"Output/Directory={outdir}", "--set", "Output/Write vtu=false", PRM]
    if PAIR:
        m = 5 * n // 4
        cmd[-1:-1] = ["--set", f"Body 2/Mesh/Subdivisions={2 * m}, {m}, {m}",
                      "--set", f"Body 2/Material/Poisson's ratio={NU}"]
    p = subprocess.run(cmd, capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    with open(os.path.join(outdir, "summary.json")) as f:
        summary = json.load(f)
    return p, summary


def measure_run(outdir):
    with open(os.path.join(outdir, "contact.csv")) as f:
        rows = list(csv.DictReader(f))
    area = {s: 2 * sum(float(r["area"]) for r in rows if r["status"] == s)
            for s in ("stick", "slip")}
    stick = [r for r in rows if r["status"] == "stick"]
    x_stick = (sum(float(r["x"]) * float(r["area"]) for r in stick) /
               sum(float(r["area"]) for r in stick)) if stick else float("nan")
    return dict(a_meas=math.sqrt((area["stick"] + area["slip"]) / math.pi),
                c_meas=math.sqrt(area["stick"] / math.pi), x_stick=x_stick,
                stick=len(stick), slip=sum(r["status"] == "slip" for r in rows))


def measure(exe, n, ratios, sliding):
    rows = []
    with tempfile.TemporaryDirectory() as work:
        P = None
        for q in [0.0] + [r for r in ratios if r > 0] + [sliding]:
            traction = 0.0 if q == 0 else q * MU * P / (4 * L * L)
            out = os.path.join(work, f"q{q}")
            p, summary = solve(exe, n, traction, out)
            if q > 1:
                ok = p.returncode == 4 and "no equilibrium" in p.stderr
                rows.append(dict(n=n, nu=NU, q=q, status=("no equilibrium reported" if ok else
                                                   f"exit {p.returncode}: {p.stderr.strip()[:200]}"),
                                 n_A=summary["hessian_multiplications"]["total"],
                                 time=summary["times"]["total"]))
                print(rows[-1], flush=True)
                continue
            if p.returncode != 0:
                raise SystemExit(f"q = {q}: exit {p.returncode}\n{p.stderr}")
            c = summary["contact"]
            # The forces on the slave: the indenter on the rigid flat, the block in the pair.
            side = -1 if PAIR else 1
            P_run = 2 * side * c["normal_force"][2]
            Q_run = -2 * side * c["tangential_force"][0]
            if P is None:
                P = P_run
            m = measure_run(out)
            a_hertz = (3 * P_run * R / (4 * E_STAR)) ** (1 / 3)
            q_meas = Q_run / (MU * P_run)
            row = dict(n=n, nu=NU, q=q, q_meas=q_meas, P=P_run, Q=Q_run, a_hertz=a_hertz,
                       c_over_a=m["c_meas"] / m["a_meas"],
                       c_theory=max(1 - q_meas, 0) ** (1 / 3),
                       n_A=summary["hessian_multiplications"]["total"],
                       time=summary["times"]["total"], status="converged", **m)
            row["x_stick"] = m["x_stick"] / m["a_meas"]
            rows.append(row)
            print({k: row[k] for k in FIELDS if k in row}, flush=True)
    return rows


def write(rows, csv_path, md_path, command):
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in FIELDS})
    out = ["<!-- written by benchmarks/cattaneo_mindlin.py -->", "", f"Command: `{command}`", "",
           "| n | ν | q = Q/(μP) | P (N) | Q (N) | a_Hertz (mm) | a_meas (mm) | c_meas (mm) | "
           "c/a measured | (1 − q)^(1/3) | stick zone centre x/a | stick / slip nodes | n_A | "
           "time (s) | status |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "converged":
            out.append(f"| {r['n']} | {r['nu']:g} | {r['q']:g} (asked) | | | | | | | | | | {r['n_A']} | "
                       f"{r['time']:.1f} | {r['status']} |")
            continue
        out.append(f"| {r['n']} | {r['nu']:g} | {r['q_meas']:.3f} | {r['P']:.0f} | {r['Q']:.0f} | "
                   f"{1e3 * r['a_hertz']:.3f} | {1e3 * r['a_meas']:.3f} | "
                   f"{1e3 * r['c_meas']:.3f} | {r['c_over_a']:.3f} | {r['c_theory']:.3f} | "
                   f"{r['x_stick']:+.3f} | {r['stick']} / {r['slip']} | {r['n_A']} | "
                   f"{r['time']:.1f} | {r['status']} |")
    with open(md_path, "w") as f:
        f.write("\n".join(out) + "\n")


def plot(csv_path, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(csv_path) as f:
        rows = [dict(r, nu=r.get("nu") or "0.3") for r in csv.DictReader(f)
                if r["status"] == "converged"]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    qs = [i / 100 for i in range(101)]
    ax.plot(qs, [(1 - q) ** (1 / 3) for q in qs], "k-",
            label="Cattaneo–Mindlin c/a = (1 − Q/μP)^(1/3)")
    for key in sorted({(r["n"], r["nu"]) for r in rows}):
        sel = [r for r in rows if (r["n"], r["nu"]) == key]
        ax.plot([float(r["q_meas"]) for r in sel], [float(r["c_over_a"]) for r in sel], "o",
                label=f"feticontact, half model n = {key[0]}, ν = {key[1]}")
    ax.set_xlabel("Q / (μP)")
    ax.set_ylabel("stick radius / contact radius")
    ax.set_xlim(0, 1.05)
    ax.set_ylim(0, 1.05)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Sphere on a steel block, μ = 0.3" if PAIR else "Sphere on a rigid flat, μ = 0.3")
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


def main():
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        plot(sys.argv[i + 1], sys.argv[i + 2])
        return
    arguments(__doc__, ["--csv", "--exe", "--markdown", "--n", "--ratios", "--sliding",
              "--poisson", "--prm"], [])
    exe = option("--exe", "build/feticontact")
    ns = [int(v) for v in option("--n", "16").split(",")]
    ratios = [float(v) for v in option("--ratios", "0,0.2,0.4,0.6,0.8,0.9").split(",")]
    sliding = float(option("--sliding", "1.2"))
    rows = []
    for n in ns:
        rows += measure(exe, n, ratios, sliding)
    write(rows, option("--csv", "doc/reports/data/cattaneo_mindlin.csv"),
          option("--markdown", "doc/reports/data/cattaneo_mindlin.md"), "python3 " + " ".join(sys.argv))


if __name__ == "__main__":
    main()
