#!/usr/bin/python3
"""Contact pressure and stick/slip map of a run: reads OUTDIR/contact.csv, writes a PNG.

    /usr/bin/python3 benchmarks/plot_contact.py OUTDIR PNG [TITLE]

Left: the normal nodal force λ_N over the contact surface (x, y); right: the status of every
contact node (open / stick / slip) with the tangential force as arrows. Needs numpy and
matplotlib (Debian's python3-numpy, python3-matplotlib).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

outdir, png = sys.argv[1], sys.argv[2]
title = sys.argv[3] if len(sys.argv) > 3 else outdir
with open(f"{outdir}/contact.csv") as f:
    rows = list(csv.DictReader(f))
x = np.array([float(r["x"]) for r in rows])
y = np.array([float(r["y"]) for r in rows])
lam = np.array([float(r["lambda_N"]) for r in rows])
t1 = np.array([float(r["lambda_T1"]) for r in rows])
t2 = np.array([float(r["lambda_T2"]) for r in rows])
status = [r["status"] for r in rows]

fig, axes = plt.subplots(1, 2, figsize=(13, 3.6))
c = axes[0].tricontourf(x, y, lam, levels=20, cmap="viridis")
fig.colorbar(c, ax=axes[0], label="normal nodal force λ_N (N)")
axes[0].set_title("normal contact force")
colors = {"open": "lightgray", "stick": "tab:blue", "slip": "tab:red"}
for s in ("open", "stick", "slip"):
    m = np.array([st == s for st in status])
    axes[1].scatter(x[m], y[m], c=colors[s], s=18, label=f"{s} ({m.sum()})")
# t1 = e_x, t2 = −e_y for the plane z = 0 with normal (0, 0, −1); force on the body = −λ_T.
axes[1].quiver(x, y, -t1, t2, color="k", width=0.002)
axes[1].legend(loc="upper right", fontsize=8)
axes[1].set_title("status and tangential force on the body")
for ax in axes:
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
fig.suptitle(title)
fig.tight_layout()
fig.savefig(png, dpi=110)
print("wrote", png)
