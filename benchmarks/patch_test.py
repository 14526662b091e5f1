#!/usr/bin/python3
"""The contact patch test on non-matching meshes (doc/validation.md, "Non-matching meshes"):

    /usr/bin/python3 benchmarks/patch_test.py [--exe build/feticontact]
        [--markdown doc/reports/data/patch_test.md] [--plot doc/reports/patch_test.png]

Runs prm/patch_test.prm (5 × 5 cubes on 7 × 7) frictionless and with μ = 0.5, and
prm/patch_test_unstructured.prm (two Gmsh meshes) frictionless and with μ = 0.5, each at
`Accuracy = reference`, and compares with the exact solution, uniaxial stress: in the lower block
u = (σ/E₁)(ν₁x, ν₁y, −z) and in the upper block u = (σ/E₂)(ν₂x, ν₂y, −(z − 0.5)) − (σ/E₁)(0, 0, 0.5)
with σ = 1e8 Pa, E₁ = 2.1e11, ν₁ = 0.3, E₂ = E₁/2, ν₂ = ν₁/2 (the same as the tests
`scene.patch_test_*`), and the pressure λ_N / D_kk = σ at every contact node. Writes the table
(largest errors) and a plot: per case the slave nodes coloured by their pressure error over the
master's vertices, and the displacement error of every vertex against its height.
Needs numpy and matplotlib for the plot.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

SIGMA, E1, NU1 = 1e8, 2.1e11, 0.3
E2, NU2 = E1 / 2, NU1 / 2
CASES = [("5 × 5 on 7 × 7", "prm/patch_test.prm", 0.0),
         ("5 × 5 on 7 × 7", "prm/patch_test.prm", 0.5),
         ("Gmsh on Gmsh", "prm/patch_test_unstructured.prm", 0.0),
         ("Gmsh on Gmsh", "prm/patch_test_unstructured.prm", 0.5)]


def exact(body, x, y, z):
    if body == 1:
        return (SIGMA / E1 * NU1 * x, SIGMA / E1 * NU1 * y, -SIGMA / E1 * z)
    return (SIGMA / E2 * NU2 * x, SIGMA / E2 * NU2 * y,
            -SIGMA / E1 * 0.5 - SIGMA / E2 * (z - 0.5))


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def run(exe, prm, mu, folder):
    cmd = [exe, "--set", f"Output/Directory={folder}", "--set", "Output/Write vtu=false",
           "--set", "Output/Write displacement csv=true",
           "--set", "Contact solver/Accuracy=reference",
           "--set", f"Contact/Zone 1/Friction coefficient={mu}", prm]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{prm} failed ({p.returncode}):\n{p.stderr}")
    vertices = []
    for r in read_rows(os.path.join(folder, "displacements.csv")):
        x, y, z = float(r["x"]), float(r["y"]), float(r["z"])
        b = int(r["body"])
        ue = exact(b, x, y, z)
        u = (float(r["ux"]), float(r["uy"]), float(r["uz"]))
        vertices.append((b, x, y, z, max(abs(a - e) for a, e in zip(u, ue)),
                         max(abs(e) for e in ue)))
    u_scale = max(v[5] for v in vertices)
    nodes = [(float(r["x"]), float(r["y"]), abs(float(r["pressure"]) - SIGMA) / SIGMA, r["status"])
             for r in read_rows(os.path.join(folder, "contact.csv"))]
    with open(os.path.join(folder, "summary.json")) as f:
        s = json.load(f)
    statuses = {}
    for n in nodes:
        statuses[n[3]] = statuses.get(n[3], 0) + 1
    return dict(vertices=[(b, x, y, z, e / u_scale) for b, x, y, z, e, _ in vertices], nodes=nodes,
                u_error=max(v[4] for v in vertices) / u_scale,
                p_error=max(n[2] for n in nodes), statuses=statuses,
                n_A=s["hessian_multiplications"]["total"])


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(2, len(results), figsize=(4.2 * len(results), 7.4))
    for j, (label, mu, r) in enumerate(results):
        ax = axes[0, j]
        master = [(x, y) for b, x, y, z, _ in r["vertices"] if b == 0 and abs(z - 0.5) < 1e-12]
        ax.plot([m[0] for m in master], [m[1] for m in master], "+", color="0.6", ms=5,
                label="master vertices (lower block)")
        err = np.array([max(n[2], 1e-17) for n in r["nodes"]])
        sc = ax.scatter([n[0] for n in r["nodes"]], [n[1] for n in r["nodes"]],
                        c=np.log10(err), cmap="viridis", s=22, vmin=-17, vmax=-8,
                        label="slave nodes (upper block)")
        fig.colorbar(sc, ax=ax, label="log10 |λ_N/D_kk − p| / p", shrink=0.8)
        ax.set_aspect("equal")
        ax.set_title(f"{label}, μ = {mu:g}", fontsize=10)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.legend(fontsize=6, loc="upper right", framealpha=0.9)
        ax = axes[1, j]
        for b, colour, name in ((0, "tab:blue", "lower block"), (1, "tab:orange", "upper block")):
            v = [(z, max(e, 1e-17)) for bb, x, y, z, e in r["vertices"] if bb == b]
            ax.semilogy([a[0] for a in v], [a[1] for a in v], ".", color=colour, ms=3, label=name)
        ax.axhline(1e-8, color="k", ls=":", lw=1, label="asked: 1e-8")
        ax.set_xlabel("z (m)")
        ax.set_ylabel("‖u − u_exact‖∞ / max ‖u_exact‖")
        ax.set_ylim(1e-17, 1e-6)
        ax.legend(fontsize=6, loc="upper right")
        ax.grid(alpha=0.3)
    fig.suptitle("Contact patch test, Accuracy = reference: pressure and displacement errors",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print("wrote", path)


def main():
    arguments(__doc__, ["--exe", "--markdown", "--plot"])
    exe = option("--exe", "build/feticontact")
    out = ["<!-- written by benchmarks/patch_test.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "| meshes | μ | contact nodes | max ‖u − u_exact‖ / max ‖u_exact‖ "
           "| max \\|λ_N / D_kk − p\\| / p | statuses | n_A |", "|---|---|---|---|---|---|---|"]
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, (label, prm, mu) in enumerate(CASES):
            r = run(exe, prm, mu, os.path.join(tmp, str(i)))
            statuses = ", ".join(f"{n} {s}" for s, n in sorted(r["statuses"].items()))
            out.append(f"| {label} | {mu:g} | {len(r['nodes'])} | {r['u_error']:.2g} | "
                       f"{r['p_error']:.2g} | {statuses} | {r['n_A']} |")
            print(out[-1], flush=True)
            results.append((label, mu, r))
    with open(option("--markdown", "doc/reports/data/patch_test.md"), "w") as f:
        f.write("\n".join(out) + "\n")
    print("\n".join(out))
    plot(results, option("--plot", "doc/reports/patch_test.png"))


if __name__ == "__main__":
    main()
