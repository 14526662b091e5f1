#!/usr/bin/env python3
"""A scene against the same scene moved rigidly: the displacements must be the moved ones.

  rotated_scene.py EXE PRM OUTDIR --rotation AXIS:ANGLE:POINT [--translation T] [--body N]...
      [--vector PATH=VALUE]... [--point PATH=VALUE]... [--set PATH=VALUE]...
      [--np N] [--moved-np N] [--moved-set PATH=VALUE]... [--moved-log TEXT] [--tolerance TOL]

The first run solves PRM with the --set and the --vector and --point entries as given. The second
moves every body named by --body (all of them by default) with its Mesh/Transform: the rotation
by ANGLE degrees about AXIS ('ax, ay, az') through POINT ('px, py, pz'), then the translation T,
and gives every --vector entry rotated and every --point entry moved the same way (an entry is
'a, b, c', or a list 'part: a, b, c; part: a, b, c' as Tractions are written; the parts are the
body's own surfaces and stay as they are; several --vector entries of one PATH are joined by
';', which CMake cannot pass in one argument). It runs on --moved-np ranks (default: --np) with the
--moved-set entries added last (they override), and must print every --moved-log TEXT. The nodal displacements of the moved run, taken back by the inverse
rotation and matched to the first run's vertices by position, must agree to TOL relative to the
largest displacement (max norm; default 1e-6), and so must the size of the total normal and
tangential contact forces (relative to the larger of them) and the largest displacement.
Standard library only.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_case import load_summary, run  # noqa: E402


def rotation_matrix(axis, angle_degrees):
    """Rodrigues' rotation matrix about the unit vector along axis, right-handed."""
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    t = math.radians(angle_degrees)
    c, s, C = math.cos(t), math.sin(t), 1 - math.cos(t)
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def apply(R, v):
    return [sum(R[i][j] * v[j] for j in range(3)) for i in range(3)]


def transpose(R):
    return [[R[j][i] for j in range(3)] for i in range(3)]


def numbers(text):
    return [float(c) for c in text.split(",")]


def text_of(v):
    return ", ".join(repr(c + 0.0) for c in v)


def map_entry(value, f):
    """'a, b, c' or 'part: a, b, c; part: a, b, c' with every vector replaced by f(vector)."""
    entries = []
    for entry in value.split(";"):
        part, colon, vector = entry.rpartition(":")
        entries.append(part + colon + " " + text_of(f(numbers(vector))))
    return "; ".join(entries).strip()


def read_csv(path):
    with open(path) as f:
        return [(int(r.get("body", 0)), [float(r[k]) for k in "xyz"],
                 [float(r[k]) for k in ("ux", "uy", "uz")]) for r in csv.DictReader(f)]


def contact_force_sizes(summary):
    c = summary.get("contact", {})
    return [math.sqrt(sum(x * x for x in c.get(key, [0, 0, 0])))
            for key in ("normal_force", "tangential_force")]


def main(args):
    exe, prm, outdir = args[:3]
    sets, moved_sets, vectors, points, bodies, logs = [], [], [], [], [], []
    rotation, translation, tol, np, moved_np = None, [0.0, 0.0, 0.0], 1e-6, 1, None
    i = 3
    while i < len(args):
        key, value = args[i], args[i + 1]
        if key == "--rotation":
            axis, angle, point = value.split(":")
            rotation = (numbers(axis), float(angle), numbers(point))
        elif key == "--translation":
            translation = numbers(value)
        elif key == "--body":
            bodies.append(int(value))
        elif key in ("--vector", "--point"):
            path, entry = value.split("=", 1)
            listed = vectors if key == "--vector" else points
            same = [item for item in listed if item[0] == path]
            if same:
                same[0][1] += "; " + entry
            else:
                listed.append([path, entry])
        elif key == "--set":
            sets += ["--set", value]
        elif key == "--moved-set":
            moved_sets += ["--set", value]
        elif key == "--np":
            np = int(value)
        elif key == "--moved-log":
            logs.append(value)
        elif key == "--moved-np":
            moved_np = int(value)
        elif key == "--tolerance":
            tol = float(value)
        else:
            raise ValueError(key)
        i += 2
    axis, angle, p = rotation
    R = rotation_matrix(axis, angle)
    move = lambda x: [a + b + c for a, b, c in zip(p, apply(R, [xi - pi for xi, pi in zip(x, p)]),
                                                   translation)]
    given = sets + [a for path, value in vectors + points for a in ("--set", path + "=" + value)]
    moved = sets + [a for path, value in vectors for a in ("--set", path + "=" + map_entry(
        value, lambda v: apply(R, v)))]
    moved += [a for path, value in points for a in ("--set", path + "=" + map_entry(value, move))]
    for b in bodies or [1]:
        base = f"Body {b}/Mesh/Transform/"
        moved += ["--set", base + "Rotation axis=" + text_of(axis),
                  "--set", base + "Rotation angle=" + repr(angle),
                  "--set", base + "Rotation point=" + text_of(p),
                  "--set", base + "Translation=" + text_of(translation)]
    moved += moved_sets
    csv_on = ["--set", "Output/Write displacement csv=true"]
    results = []
    for name, extra, ranks in (("given", given, np), ("moved", moved, moved_np or np)):
        d = outdir + "_" + name
        completed = run(exe, prm, d, ranks, extra + csv_on)
        if completed.returncode != 0:
            print(f"FAILED: the {name} scene exited with status {completed.returncode}")
            return 1
        results.append((load_summary(os.path.join(d, "summary.json")),
                        read_csv(os.path.join(d, "displacements.csv"))))
        for text in logs if name == "moved" else []:
            if text not in completed.stdout:
                print(f"FAILED: the moved scene does not print <{text}>")
                return 1
    (s0, rows0), (s1, rows1) = results
    # The moved vertices taken back to the first run's frame, matched by rounded position.
    Rt = transpose(R)
    back = lambda x: [a + b for a, b in zip(p, apply(Rt, [xi - ti - pi for xi, ti, pi in
                                                          zip(x, translation, p)]))]
    size = max(max(abs(c) for _, x, _ in rows0 for c in x), 1e-300)
    key = lambda body, x: (body,) + tuple(round(c / size, 7) for c in x)
    given_u = {key(b, x): u for b, x, u in rows0}
    moved_u = {key(b, back(x)): apply(Rt, u) for b, x, u in rows1}
    ok = set(given_u) == set(moved_u) and len(given_u) == len(rows0)
    if not ok:
        print(f"FAILED: the vertices differ ({len(given_u)} against {len(moved_u)} matched)")
        return 1
    scale = max(abs(c) for u in given_u.values() for c in u)
    diff = max(abs(a - b) for k in given_u for a, b in zip(given_u[k], moved_u[k]))
    good = diff <= tol * scale
    print(f"  displacements moved back against the given scene: max difference "
          f"{diff / scale:.3e} of max |u| (tolerance {tol:g}) -> {'ok' if good else 'FAILED'}")
    ok &= good
    f0, f1 = contact_force_sizes(s0), contact_force_sizes(s1)
    force_scale = max(f0 + [1e-300])
    for what, a, b in zip(("normal", "tangential"), f0, f1):
        good = abs(a - b) <= tol * force_scale
        print(f"  |total {what} contact force|: {a:.10g} and {b:.10g} -> {'ok' if good else 'FAILED'}")
        ok &= good
    for (what, summary) in (("given", s0), ("moved", s1)):
        print(f"  {what}: {summary['outer_iterations']} outer iterations, "
              f"{summary['hessian_multiplications']['total']} Hessian multiplications")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
