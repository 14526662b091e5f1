#!/usr/bin/env python3
"""The polygonal baseline approaches the disc as s grows.

For the brick with Tresca friction (a given slip bound g on every contact node), solves the disc
problem (MPGP variant) and the polygonal problems with s = 2, 4, 8, 16 tangential multipliers
per node, and requires the displacement difference polygon − disc (max norm, relative) to
decrease strictly with s, and for s ≥ 4 to stay within twice the polygon's geometric gap: the
inscribed 2s-gon lies between the radii g cos(π/2s) and g, a relative gap 1 − cos(π/2s) = O(1/s²)
(measured ratios 0.8 to 1.2). Usage: polygon_convergence.py EXE PRM OUTDIR. Standard library only.
"""
import csv
import math
import os
import shutil
import subprocess
import sys

exe, prm, outdir = sys.argv[1:4]
common = ["--set", "Output/Write vtu=false", "--set", "Output/Write displacement csv=true",
          "--set", "Contact solver/Friction law=tresca", "--set", "Contact solver/Slip bound=1e6"]


def run(name, sets):
    d = os.path.join(outdir, name)
    if os.path.isdir(d):
        shutil.rmtree(d)
    cmd = [exe, "--set", f"Output/Directory={d}", *common, *sets, prm]
    print("$", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, capture_output=True, timeout=600)
    with open(os.path.join(d, "displacements.csv")) as f:
        return [[float(r[k]) for k in ("ux", "uy", "uz")] for r in csv.DictReader(f)]


disc = run("disc", ["--set", "Contact solver/Algorithm=mpgp"])
scale = max(abs(c) for row in disc for c in row)
differences = []
for s in (2, 4, 8, 16):
    poly = run(f"s{s}", ["--set", "Contact solver/Algorithm=polygonal",
                         "--set", f"Contact solver/Expert/Polygon directions={s}"])
    diff = max(abs(a - b) for ra, rb in zip(disc, poly) for a, b in zip(ra, rb)) / scale
    differences.append(diff)
    print(f"  s = {s:2d}: max |u_polygon − u_disc| / max |u_disc| = {diff:.3e}"
          f"   (1 − cos(π/2s) = {1 - math.cos(math.pi / (2 * s)):.3e})")
ok = all(b < a for a, b in zip(differences, differences[1:]))
print("  decreasing with s:", "ok" if ok else "FAILED")
ok_bound = True
for s, diff in zip((4, 8, 16), differences[1:]):
    gap = 1 - math.cos(math.pi / (2 * s))
    good = diff <= 2 * gap
    ok_bound &= good
    print(f"  s = {s:2d}: difference / geometric gap = {diff / gap:.2f} (≤ 2):", "ok" if good else "FAILED")
sys.exit(0 if ok and ok_bound else 1)
