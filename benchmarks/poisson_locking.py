#!/usr/bin/env python3
"""P1 locking as ν → 1/2 on the paper's brick (doc/formulation.md, "The brick benchmark"; μ = 0.3, MPGP, default tolerances).

    python3 benchmarks/poisson_locking.py [--exe build/feticontact] [--k 4,8,16]
        [--nu 0,0.3,0.45,0.49,0.499] [--markdown doc/reports/data/poisson_locking.md]

For each ν and k (Subdivisions 3k, k, k) the brick is solved and the displacement of its free
corner (3, 1, 1), a vertex of every mesh, is compared with that on the finest mesh: linear
tetrahedra lock as ν → 1/2 (the discrete displacements cannot be divergence-free without
locking the mesh), so the coarse meshes become too stiff and |u_k| / |u_finest| falls below 1
the more, the closer ν is to 1/2. Also: MSA iterations, Hessian multiplications n_A, the
numbers of stick and slip nodes. Standard library only.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

PRM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "prm", "kucera_table_2.prm")
CORNER = (3.0, 1.0, 1.0)


def run(exe, k, nu):
    with tempfile.TemporaryDirectory() as out:
        result = subprocess.run(
            [exe, "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
             "--set", f"Body 1/Material/Poisson's ratio={nu}",
             "--set", "Contact solver/Algorithm=mpgp", "--set", "Output/Write vtu=false",
             "--set", "Output/Write displacement csv=true", "--set", f"Output/Directory={out}",
             PRM], capture_output=True, text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if result.returncode != 0:
            return None, f"exit {result.returncode}"
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        with open(os.path.join(out, "displacements.csv")) as f:
            for row in csv.DictReader(f):
                x = tuple(float(row[c]) for c in ("x", "y", "z"))
                if max(abs(a - b) for a, b in zip(x, CORNER)) < 1e-9:
                    u = [float(row[c]) for c in ("ux", "uy", "uz")]
                    return dict(u=u, norm=math.sqrt(sum(c * c for c in u)),
                                iter=summary["outer_iterations"],
                                n_A=summary["hessian_multiplications"]["total"],
                                stick=summary["contact"]["stick"],
                                slip=summary["contact"]["slip"]), "converged"
    return None, "corner not found"


def main():
    arguments(__doc__, ["--exe", "--k", "--markdown", "--nu"], [])
    exe = option("--exe", "build/feticontact")
    ks = [int(v) for v in option("--k", "4,8,16").split(",")]
    nus = [float(v) for v in option("--nu", "0,0.3,0.45,0.49,0.499").split(",")]
    md_path = option("--markdown", "doc/reports/data/poisson_locking.md")
    results = {}
    for nu in nus:
        for k in ks:
            r, status = run(exe, k, nu)
            results[nu, k] = r
            print(f"ν = {nu}, k = {k}: {status}" +
                  (f", |u(corner)| = {r['norm']:.6e}, n_A = {r['n_A']}" if r else ""), flush=True)
    command = " ".join(["python3"] + sys.argv)
    out = ["<!-- written by benchmarks/poisson_locking.py -->", "", f"Command: `{command}`", "",
           "|u| at the free corner (3, 1, 1) on mesh k over that on the finest mesh "
           f"(k = {ks[-1]}); Iter / n_A / stick / slip per run.", "",
           "| ν | " + " | ".join(f"k = {k}: \\|u\\| (m)" for k in ks) + " | " +
           " | ".join(f"k = {k} / k = {ks[-1]}" for k in ks[:-1]) + " | " +
           " | ".join(f"k = {k}: Iter / n_A / stick / slip" for k in ks) + " |",
           "|---" * (2 * len(ks) + len(ks) - 1 + 1) + "|"]
    for nu in nus:
        cells = [f"{nu:g}"]
        fine = results[nu, ks[-1]]
        for k in ks:
            r = results[nu, k]
            cells.append(f"{r['norm']:.4e}" if r else "failed")
        for k in ks[:-1]:
            r = results[nu, k]
            cells.append(f"{r['norm'] / fine['norm']:.3f}" if r and fine else "–")
        for k in ks:
            r = results[nu, k]
            cells.append(f"{r['iter']} / {r['n_A']} / {r['stick']} / {r['slip']}" if r else "–")
        out.append("| " + " | ".join(cells) + " |")
    text = "\n".join(out) + "\n"
    os.makedirs(os.path.dirname(md_path), exist_ok=True)
    with open(md_path, "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
