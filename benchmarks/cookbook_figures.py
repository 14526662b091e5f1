#!/usr/bin/python3
"""The pictures of the cookbooks (doc/cookbooks.md): runs the scenes of prm/ and plots them.

    /usr/bin/python3 benchmarks/cookbook_figures.py [--exe build/feticontact] [--outdir DIR]
                                                    [--no-run] [--scenes a,b,...]

Runs every scene of prm/ once, one run at a time, with the executable --exe (default
build/feticontact), each into DIR/<scene> (default: a folder under the system's temporary
directory, printed at the end) with `Output/Write displacement csv = true`, and keeps the
console output as DIR/<scene>.console.txt. Then it reads the CSV outputs (contact.csv,
history.csv, displacements.csv) and summary.json and writes doc/cookbook_<name>.png. --no-run
plots from the folders of an earlier run in --outdir. Needs numpy and matplotlib.

Frames: where the slave's normal is (0, 0, −1) (a body on a floor or a lower body) the code's
tangents are t1 = e_x, t2 = −e_y, and the tangential force on the slave is −λ_T, i.e.
(−λ_T1, +λ_T2) in (x, y). Where it is (0, 0, 1) (the flat block under the indenter of
cattaneo_mindlin_pair) t1 = e_x, t2 = e_y, and the force on the master (the indenter) is
(λ_T1, λ_T2).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.tri as mtri
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["brick", "brick_gmsh", "brick_contact", "brick_gmsh_contact", "kucera_table_1",
          "kucera_table_2", "kucera_table_3", "hertz", "cattaneo_mindlin", "two_blocks",
          "two_blocks_nonmatching", "patch_test", "patch_test_unstructured", "hertz_two_bodies",
          "cattaneo_mindlin_pair"]
STATUS_COLORS = {"open": "lightgray", "stick": "tab:blue", "slip": "tab:red"}


def run(exe, scene, outdir):
    folder = os.path.join(outdir, scene)
    cmd = [exe, "--set", f"Output/Directory={folder}",
           "--set", "Output/Write displacement csv=true", f"prm/{scene}.prm"]
    print("running", " ".join(cmd), flush=True)
    res = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    with open(os.path.join(outdir, f"{scene}.console.txt"), "w") as f:
        f.write(res.stdout)
        f.write(res.stderr)
    if res.returncode != 0:
        print(f"  {scene}: exit status {res.returncode}", file=sys.stderr)


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    out = {}
    for key in rows[0].keys():
        try:
            out[key] = np.array([float(r[key]) for r in rows])
        except ValueError:
            out[key] = np.array([r[key] for r in rows])
    return out


def contact(outdir, scene):
    return read_csv(os.path.join(outdir, scene, "contact.csv"))


def summary(outdir, scene):
    with open(os.path.join(outdir, scene, "summary.json")) as f:
        return json.load(f)


def status_map(ax, c, title, arrows=True, force=None):
    """Contact nodes coloured by status, tangential force on the body as arrows (by default
    (−λ_T1, λ_T2), the force on a slave with the normal (0, 0, −1))."""
    for s in ("open", "stick", "slip"):
        m = c["status"] == s
        ax.scatter(c["x"][m], c["y"][m], c=STATUS_COLORS[s], s=14, label=f"{s} ({m.sum()})",
                   zorder=2)
    if arrows:
        fx, fy = force if force is not None else (-c["lambda_T1"], c["lambda_T2"])
        ax.quiver(c["x"], c["y"], fx, fy, color="k", width=0.003, zorder=3)
    ax.legend(loc="upper right", fontsize=7, framealpha=0.9)
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def pressure_map(fig, ax, c, title, unit=1.0, label="contact pressure (Pa)"):
    t = mtri.Triangulation(c["x"], c["y"])
    p = c["pressure"] / unit
    levels = np.linspace(0, p.max(), 21)
    cf = ax.tricontourf(t, p, levels=levels, cmap="viridis")
    fig.colorbar(cf, ax=ax, label=label, shrink=0.85)
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def history(ax, outdir, scene, title, x="smalbe_iteration"):
    h = read_csv(os.path.join(outdir, scene, "history.csv"))
    it = h[x]
    ax.semilogy(it, np.maximum(h["feasibility"], 1e-16), label="‖Gλ − e‖ (relative)")
    ax.semilogy(it, np.maximum(h["projected_gradient"], 1e-16), label="‖g^P‖ (relative)")
    ch = h["slip_bound_change"]
    ax.semilogy(it[ch > 0], ch[ch > 0], label="change of the slip bound")
    ax.set_xlabel("SMALBE iteration" if x == "smalbe_iteration" else x)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def face(d, body, axis, value, tol=1e-9):
    m = (d["body"] == body) & (np.abs(d[axis] - value) < tol)
    return m


def deformed_face(fig, ax, d, masks, a, b, title, scale=None, cbar=True):
    """The faces given by masks (in the plane of coordinates a, b) deformed, coloured by |u|."""
    umag = np.sqrt(d["ux"] ** 2 + d["uy"] ** 2 + d["uz"] ** 2)
    if scale is None:
        size = max(d["x"].max() - d["x"].min(), d["z"].max() - d["z"].min())
        scale = 0.1 * size / umag.max()
    vmax = umag.max()
    for m in masks:
        t = mtri.Triangulation(d[a][m], d[b][m])
        ax.triplot(t, color="0.75", lw=0.4)
        td = mtri.Triangulation(d[a][m] + scale * d["u" + a][m], d[b][m] + scale * d["u" + b][m],
                                t.triangles)
        cf = ax.tripcolor(td, umag[m], shading="gouraud", cmap="plasma", vmin=0, vmax=vmax)
        ax.triplot(td, color="k", lw=0.2)
    if cbar:
        fig.colorbar(cf, ax=ax, label="|u| (m)", shrink=0.85)
    ax.set_title(f"{title} (displacements × {scale:.3g})", fontsize=10)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{a} (m)")
    ax.set_ylabel(f"{b} (m)")
    return scale


def save(fig, name):
    path = os.path.join(ROOT, "doc", f"cookbook_{name}.png")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print("wrote", os.path.relpath(path, ROOT))


def plot_brick(outdir):
    fig, axes = plt.subplots(2, 2, figsize=(12, 5.6))
    for row, scene in enumerate(("brick", "brick_gmsh")):
        d = read_csv(os.path.join(outdir, scene, "displacements.csv"))
        deformed_face(fig, axes[row, 0], d, [face(d, 0, "y", 0.0)], "x", "z",
                      f"{scene}: face y = 0")
        deformed_face(fig, axes[row, 1], d, [face(d, 0, "z", 1.0)], "x", "y",
                      f"{scene}: top face z = 1")
    save(fig, "brick")


def plot_brick_contact(outdir, scene, title):
    c = contact(outdir, scene)
    fig, axes = plt.subplots(1, 3, figsize=(17, 3.7), gridspec_kw={"width_ratios": [1.2, 1, 0.8]})
    pressure_map(fig, axes[0], c, "contact pressure λ_N / area", unit=1e6,
                 label="pressure (MPa)")
    status_map(axes[1], c, "status and tangential force on the brick")
    history(axes[2], outdir, scene, "convergence (history.csv)")
    fig.suptitle(title)
    save(fig, scene)


def plot_kucera(outdir):
    fig, axes = plt.subplots(2, 3, figsize=(17, 6.4))
    titles = {"kucera_table_1": "Table 1: μ = 0.1, Algorithm 2",
              "kucera_table_2": "Table 2: μ = 0.3, Algorithm 2",
              "kucera_table_3": "Table 3: μ = 0.3, square (s = 2)"}
    for j, scene in enumerate(titles):
        status_map(axes[0, j], contact(outdir, scene), titles[scene])
        history(axes[1, j], outdir, scene, f"{scene}: convergence")
    save(fig, "kucera_tables")


def plot_hertz(outdir):
    c = contact(outdir, "hertz")
    h = summary(outdir, "hertz")["hertz"]
    a, p0 = h["a_hertz"], h["p0_hertz"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    m = np.hypot(c["x"], c["y"]) < 2.2 * a
    sub = {k: v[m] for k, v in c.items()}
    pressure_map(fig, axes[0], sub, "contact pressure near the contact point (quarter model)",
                 unit=1e9, label="pressure (GPa)")
    th = np.linspace(0, np.pi / 2, 50)
    axes[0].plot(a * np.cos(th), a * np.sin(th), "w--", lw=1, label="Hertz radius a")
    axes[0].legend(fontsize=7, loc="upper right")
    r = np.hypot(c["x"], c["y"])
    rr = np.linspace(0, a, 200)
    axes[1].plot(rr * 1e3, p0 * np.sqrt(1 - (rr / a) ** 2) / 1e9, "k-", label="Hertz p(r)")
    axes[1].plot(r[m] * 1e3, c["pressure"][m] / 1e9, "o", ms=3, label="λ_N / area per node")
    axes[1].set_xlabel("r (mm)")
    axes[1].set_ylabel("pressure (GPa)")
    axes[1].set_title(f"a = {h['a'] * 1e3:.3f} mm (Hertz {a * 1e3:.3f}), "
                      f"p0 = {h['p0'] / 1e9:.2f} GPa (Hertz {p0 / 1e9:.2f})", fontsize=10)
    axes[1].legend(fontsize=8)
    axes[1].grid(alpha=0.3)
    save(fig, "hertz")


def plot_cattaneo_mindlin(outdir, scene="cattaneo_mindlin", Q=750.0, pair=False):
    """The rigid flat (E* = E/(1 − ν²), the indenter the slave) or the pair of similar bodies
    (E* = E/(2(1 − ν²)), the block the slave, the force on the indenter (λ_T1, λ_T2))."""
    c = contact(outdir, scene)
    mu, R, E, nu = 0.3, 0.02, 2.1e11, 0.3
    E_star = E / (1 - nu ** 2) / (2 if pair else 1)
    P = 2 * c["lambda_N"].sum()                       # a half model
    a = (3 * P * R / (4 * E_star)) ** (1 / 3)
    ratio_q = Q / (mu * P)
    cr = a * (1 - ratio_q) ** (1 / 3)
    r = np.hypot(c["x"], c["y"])
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.4))
    m = r < 1.6 * a
    sub = {k: v[m] for k, v in c.items()}
    status_map(axes[0], sub, "status and tangential force on the indenter (half model)",
               force=(sub["lambda_T1"], sub["lambda_T2"]) if pair else None)
    th = np.linspace(0, np.pi, 80)
    axes[0].plot(a * np.cos(th), a * np.sin(th), "k--", lw=1)
    axes[0].plot(cr * np.cos(th), cr * np.sin(th), "k:", lw=1)
    axes[0].text(0, a * 1.03, "a (Hertz)", ha="center", fontsize=7)
    axes[0].text(0, cr * 0.85, "c", ha="center", fontsize=7)
    pressed = c["status"] != "open"
    ratio = np.hypot(c["lambda_T1"], c["lambda_T2"])[pressed] / (mu * c["lambda_N"][pressed])
    axes[1].plot(r[pressed] * 1e3, ratio, "o", ms=3, label="‖λ_T‖ / (μ λ_N) per pressed node")
    rr = np.linspace(0, a * 0.999, 300)
    th_ratio = np.where(rr < cr, 1 - np.sqrt(np.maximum(cr ** 2 - rr ** 2, 0))
                        / np.sqrt(a ** 2 - rr ** 2), 1.0)
    axes[1].plot(rr * 1e3, th_ratio, "k-", label="Cattaneo–Mindlin")
    axes[1].axvline(cr * 1e3, color="0.5", ls=":")
    axes[1].set_xlabel("r (mm)")
    axes[1].set_ylabel("‖λ_T‖ / (μ λ_N)")
    axes[1].set_ylim(0, 1.1)
    axes[1].set_title(f"P = {P:.0f} N, Q/(μP) = {ratio_q:.2f}, c/a = {cr / a:.2f}",
                      fontsize=10)
    axes[1].legend(fontsize=8, loc="lower right")
    axes[1].grid(alpha=0.3)
    fig.suptitle(f"{scene}: " + ("an elastic indenter on an elastic block (same E, ν)" if pair
                                 else "an elastic indenter on a rigid flat"), fontsize=11)
    save(fig, scene)


def plot_two_blocks(outdir, scene="two_blocks"):
    c = contact(outdir, scene)
    d = read_csv(os.path.join(outdir, scene, "displacements.csv"))
    fig = plt.figure(figsize=(13, 7.4))
    gs = fig.add_gridspec(2, 2, width_ratios=[2, 1.1])
    ax0 = fig.add_subplot(gs[0, 0])
    ax1 = fig.add_subplot(gs[0, 1])
    ax2 = fig.add_subplot(gs[1, :])
    for ax, z, title in ((ax0, 1, "zone 1: lower block on the rigid plane (μ = 0.3)"),
                         (ax1, 2, "zone 2: upper block on the lower block (μ = 0.5)")):
        m = c["zone"] == z
        status_map(ax, {k: v[m] for k, v in c.items()}, title)
    bodies = sorted(set(d["body"]))
    deformed_face(fig, ax2, d, [face(d, b, "y", 0.0) for b in bodies], "x", "z",
                  "face y = 0 of both blocks")
    if scene != "two_blocks":
        fig.suptitle(f"{scene}: the upper block meshed 6 × 6 × 3, mortar rows in zone 2",
                     fontsize=11)
    save(fig, scene)


def plot_patch_tests(outdir):
    """Per patch test: the face y = 0 of both blocks deformed, and the slave nodes over the
    master's vertices on the interface, coloured by the pressure λ_N / D_kk."""
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.6))
    for row, scene in enumerate(("patch_test", "patch_test_unstructured")):
        d = read_csv(os.path.join(outdir, scene, "displacements.csv"))
        c = contact(outdir, scene)
        # The vertices on y = 0 of a Gmsh mesh lie on the plane only to rounding.
        deformed_face(fig, axes[row, 0], d, [face(d, b, "y", 0.0, 1e-6) for b in (0, 1)],
                      "x", "z", f"{scene}: face y = 0")
        ax = axes[row, 1]
        m = face(d, 0, "z", 0.5, 1e-6)
        ax.plot(d["x"][m], d["y"][m], "+", color="0.5", ms=6, label="master vertices (lower block)")
        sc = ax.scatter(c["x"], c["y"], c=c["pressure"] / 1e8 - 1, cmap="coolwarm", s=26,
                        label="slave nodes (upper block)", zorder=3)
        fig.colorbar(sc, ax=ax, label="(λ_N / D_kk − p) / p, p = 1e8 Pa", shrink=0.85,
                     format="%.1e")
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title("interface z = 0.5: slave nodes over the master's vertices", fontsize=10)
        ax.legend(fontsize=7, loc="upper right", framealpha=0.9)
    save(fig, "patch_tests")


def plot_hertz_two_bodies(outdir):
    c = contact(outdir, "hertz_two_bodies")
    d = read_csv(os.path.join(outdir, "hertz_two_bodies", "displacements.csv"))
    h = summary(outdir, "hertz_two_bodies")["hertz"]
    a, R = h["a_hertz"], 0.02
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.6), gridspec_kw={"width_ratios": [1.1, 1, 1.2]})
    m = np.hypot(c["x"], c["y"]) < 2.2 * a
    sub = {k: v[m] for k, v in c.items()}
    pressure_map(fig, axes[0], sub, "pressure λ_N / D_kk on the block's top (the slave)",
                 unit=1e9, label="pressure (GPa)")
    th = np.linspace(0, np.pi / 2, 50)
    axes[0].plot(a * np.cos(th), a * np.sin(th), "w--", lw=1, label="Hertz radius a")
    axes[0].legend(fontsize=7, loc="upper right")
    ax = axes[1]
    partly = c["D_kk"] < (1 - 1e-8) * c["area"]
    pressed = c["status"] != "open"
    for mask, colour, label in ((~partly & ~pressed, "lightgray", "open"),
                                (pressed, "tab:red", "pressed"),
                                (partly, "tab:blue", "partly covered (weighted by φ_k)")):
        ax.scatter(c["x"][mask] * 1e3, c["y"][mask] * 1e3, s=6, c=colour,
                   label=f"{label} ({mask.sum()})")
    ax.plot(a * np.cos(th) * 1e3, a * np.sin(th) * 1e3, "k--", lw=1, label="Hertz radius a")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("the zone's contact nodes (within the search distance)", fontsize=10)
    ax.legend(fontsize=7, loc="upper right", framealpha=0.9)
    ax = axes[2]
    on = np.abs(d["y"]) < 1e-12
    block = on & (d["body"] == 2) & (np.abs(d["z"]) < 1e-12)
    indenter = on & (d["body"] == 1) & (d["z"] <= R - np.sqrt(np.maximum(R ** 2 - d["x"] ** 2, 0))
                                         + 1e-9)
    for mask, colour, label in ((indenter, "tab:orange", "indenter's bottom"),
                                (block, "tab:purple", "block's top")):
        order = np.argsort(d["x"][mask])
        x, z = d["x"][mask][order], d["z"][mask][order]
        ux, uz = d["ux"][mask][order], d["uz"][mask][order]
        near = x < 3 * a
        ax.plot(x[near] * 1e3, z[near] * 1e6, ":", color=colour, lw=1)
        ax.plot((x + ux)[near] * 1e3, (z + uz)[near] * 1e6, ".-", color=colour, ms=3,
                label=f"{label}, deformed (dotted: before)")
    ax.axvline(a * 1e3, color="0.5", ls="--", lw=1, label="Hertz radius a")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (µm)")
    ax.set_title("the surfaces in the plane y = 0", fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    fig.suptitle(f"hertz_two_bodies: a = {h['a'] * 1e3:.3f} mm (Hertz {a * 1e3:.3f}), "
                 f"p0 = {h['p0'] / 1e9:.2f} GPa (Hertz {h['p0_hertz'] / 1e9:.2f})", fontsize=11)
    save(fig, "hertz_two_bodies")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "feticontact"))
    ap.add_argument("--outdir", default=None)
    ap.add_argument("--no-run", action="store_true")
    ap.add_argument("--scenes", default=",".join(SCENES))
    args = ap.parse_args()
    outdir = args.outdir or tempfile.mkdtemp(prefix="cookbook_")
    os.makedirs(outdir, exist_ok=True)
    scenes = [s for s in args.scenes.split(",") if s]
    if not args.no_run:
        for s in scenes:
            run(os.path.abspath(args.exe), s, outdir)
    have = lambda *names: all(os.path.exists(os.path.join(outdir, n, "summary.json"))
                              for n in names)
    if have("brick", "brick_gmsh"):
        plot_brick(outdir)
    if have("brick_contact"):
        plot_brick_contact(outdir, "brick_contact", "brick_contact: k = 8, μ = 0.3, defaults")
    if have("brick_gmsh_contact"):
        plot_brick_contact(outdir, "brick_gmsh_contact",
                           "brick_gmsh_contact: the Gmsh mesh k = 4, μ = 0.3, defaults")
    if have("kucera_table_1", "kucera_table_2", "kucera_table_3"):
        plot_kucera(outdir)
    if have("hertz"):
        plot_hertz(outdir)
    if have("cattaneo_mindlin"):
        plot_cattaneo_mindlin(outdir)
    if have("two_blocks"):
        plot_two_blocks(outdir)
    if have("two_blocks_nonmatching"):
        plot_two_blocks(outdir, "two_blocks_nonmatching")
    if have("patch_test", "patch_test_unstructured"):
        plot_patch_tests(outdir)
    if have("hertz_two_bodies"):
        plot_hertz_two_bodies(outdir)
    if have("cattaneo_mindlin_pair"):
        plot_cattaneo_mindlin(outdir, "cattaneo_mindlin_pair", Q=1000.0, pair=True)
    print("outputs in", outdir)


if __name__ == "__main__":
    main()
