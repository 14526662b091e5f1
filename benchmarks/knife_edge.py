#!/usr/bin/env python3
"""Which surface to make the slave where one surface ends inside the other (doc/contact.md,
"Edge of the contact region"):

    /usr/bin/python3 benchmarks/knife_edge.py [--exe build/feticontact]
        [--markdown doc/reports/data/knife_edge.md]

The upper block of prm/two_blocks_nonmatching.prm moved to (1.5, 2.5) × (0, 1) × (0.5, 1), half
over the end x = 2 of the lower block, and pressed by 5e7 Pa: the lower block's edge x = 2 is a
knife edge under the upper block's bottom. Two choices of the slave, each on the scene's meshes
and on meshes refined twice: the upper block's bottom (the lower block's edge then lies inside
the slave surface, under partly covered slave nodes) and the lower block's top (its edge is a
row of fully covered slave nodes). Measured: the largest |uz(upper) − uz(lower)| over the
vertices of both blocks on the edge x = 2, z = 0.5, against the largest displacement.
Standard library only.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

from cli import arguments, option

SCENE = ["Body 2/Mesh/Lower corner=1.5, 0, 0.5", "Body 2/Mesh/Upper corner=2.5, 1, 1",
         "Body 2/Boundary conditions/Tractions=z = zmax: 0, 0, -5e7"]
MESHES = {"scene's": ["Body 1/Mesh/Subdivisions=16, 8, 4", "Body 2/Mesh/Subdivisions=6, 6, 3"],
          "refined": ["Body 1/Mesh/Subdivisions=32, 16, 8", "Body 2/Mesh/Subdivisions=12, 12, 6"]}
SLAVES = {"upper block's bottom": [],
          "lower block's top": ["Contact/Zone 2/Body=1", "Contact/Zone 2/Surface=z = zmax",
                                "Contact/Zone 2/Master body=2",
                                "Contact/Zone 2/Master surface=z = zmin"]}


def edge_separation(folder):
    u = {}
    with open(os.path.join(folder, "displacements.csv")) as f:
        for r in csv.DictReader(f):
            u[(r["body"], round(float(r["x"]), 9), round(float(r["y"]), 9),
               round(float(r["z"]), 9))] = [float(r[c]) for c in ("ux", "uy", "uz")]
    u_max = max(max(abs(c) for c in v) for v in u.values())
    worst = 0.0
    for key, v in u.items():
        if key[0] == "0" and abs(key[1] - 2) < 1e-9 and key[3] == 0.5:
            w = u.get(("1",) + key[1:])
            if w is not None:
                worst = max(worst, abs(w[2] - v[2]))
    return worst, u_max


def run(exe, sets):
    with tempfile.TemporaryDirectory() as out:
        cmd = [exe, "--set", f"Output/Directory={out}", "--set", "Output/Write vtu=false",
               "--set", "Output/Write displacement csv=true"]
        for s in SCENE + sets:
            cmd += ["--set", s]
        p = subprocess.run(cmd + ["prm/two_blocks_nonmatching.prm"], capture_output=True,
                           text=True)
        if p.returncode != 0:
            raise SystemExit(f"run failed ({p.returncode}):\n{p.stderr}")
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        separation, u_max = edge_separation(out)
    return dict(separation=separation, u_max=u_max, n_A=s["hessian_multiplications"]["total"])


def main():
    arguments(__doc__, ["--exe", "--markdown"])
    exe = option("--exe", "build/feticontact")
    out = ["<!-- written by benchmarks/knife_edge.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`", "",
           "| slave surface | meshes | largest displacement [m] | separation at the edge [m] "
           "| separation / largest displacement | n_A |", "|---|---|---|---|---|---|"]
    for slave, slave_sets in SLAVES.items():
        for mesh, mesh_sets in MESHES.items():
            r = run(exe, slave_sets + mesh_sets)
            print(slave, mesh, r, flush=True)
            out.append(f"| {slave} | {mesh} | {r['u_max']:.3g} | {r['separation']:.2g} | "
                       f"{r['separation'] / r['u_max']:.2g} | {r['n_A']} |")
    with open(option("--markdown", "doc/reports/data/knife_edge.md"), "w") as f:
        f.write("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
