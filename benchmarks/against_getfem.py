#!/usr/bin/env python3
"""This project against GetFEM 5.4 on the paper's brick with Coulomb friction: process wall time
of each code and the difference of their displacements, on the same mesh.

    /usr/bin/python3 benchmarks/against_getfem.py [--exe build/feticontact]
        [--cases F0.3_k8,F0.3_k12,F0.3_k16,F0.3_k24,F0.1_k12] [--repeats 3]
        [--repeats-large 1] [--csv doc/reports/data/against_getfem.csv]
        [--markdown doc/reports/data/against_getfem.md] [--plot doc/reports/against_getfem.png] [--report-only]

The scene is prm/brick_contact.prm: the steel brick (0,3)×(0,1)×(0,1) m, E = 2.12e11 Pa,
ν = 0.277, clamped on x = 0, tractions (2e7, 0, −1e8) Pa on z = 1 and (0, 3e7, 0) Pa on x = 3,
on the rigid flat foundation z < 0 with Coulomb friction F on z = 0; P1 tetrahedra on the box
of 3k × k × k cubes, each cube split into the six tetrahedra around its diagonal from the lowest
to the highest corner (the Kuhn split: the six monotone lattice paths; `subdivided_box_kuhn` in
source/scene/mesh_generation.cc). A case `F<F>_k<k>` is that scene with friction coefficient F
on the mesh of size h = 1/k; n = 3 (3k+1)(k+1)² is the number of displacement unknowns.

Each repeat of a case runs, one after the other, as two separate processes:

1. this project with its defaults: `<exe> prm/brick_contact.prm --set "Body 1/Mesh/Subdivisions=
   3k, k, k" --set "Contact/Zone 1/Friction coefficient=F" --set "Output/Directory=<temporary>"`
   (everything else as in the scene, including its ParaView files and displacements.csv). The
   run counts only with exit status 0 and `converged` true in summary.json; otherwise the script
   stops.
2. GetFEM 5.4 (the Python interface, `import getfem`) on the same mesh, in a new process of
   this interpreter: `against_getfem.py --getfem-run k F MESH OUTDIR` (an internal mode, run by
   the script itself; MESH names how the mesh is built, see below). The P1 vector element
   `FEM_PK(3,1)`, `IM_TETRAHEDRON(1)` (exact for P1 stiffness and constant tractions), the
   isotropic linearized elasticity brick with the Lamé coefficients of E and ν, u = 0 on x = 0
   by elimination (`add_Dirichlet_condition_with_simplification`), the tractions as source terms
   on the two faces, and `add_nodal_contact_with_rigid_obstacle_brick` on z = 0 with the
   friction coefficient F and the non-symmetric Alart–Curnier augmentation (version 1,
   augmentation parameter r = 10 E), solved by GetFEM's Newton method (`Model.solve` with
   max_iter 100, max_res 1e-10, lsolver mumps). The process writes the displacement of every
   node, the Newton iterations and its own phase times; Newton must converge, otherwise the
   script stops.
   Two details of the GetFEM model, both without effect on the discrete solution:
   - It is written in units of E (Young's modulus 1, tractions t/E, r = 10): displacements come
     out in metres unchanged, forces are multiplied back by E. GetFEM's Newton residual mixes
     the force rows of u with the multipliers' rows (displacement-sized); in SI units the
     friction rows are below its stopping test and Newton stops after one step with zero
     friction forces.
   - The obstacle level set is `z + Heaviside(1e-9 - x)`: the foundation z < 0 lifted by 1 m
     under the clamped edge x = 0, whose nodes are then never in contact (as in the project,
     where the contact nodes are those of z = 0 without x = 0). A contact multiplier on a node
     whose displacement is eliminated would make Newton's matrix singular.

Same mesh: GetFEM's mesh is `Mesh('regular simplices', X, Y, Z)` on the lattice of the box if its
tetrahedra are the Kuhn split; the script checks that before anything is timed, for every k of
the chosen cases: every convex has four lattice vertices that, sorted by coordinate sum, form a
monotone lattice path (unit steps along three different axes) from a cube's lowest corner to its
highest, inside the box, and the (cube, path) pairs are 6 · 3k · k · k distinct ones, i.e. all
six paths of every cube. If 'regular simplices' fails the check, the Kuhn tetrahedra are built
explicitly (`Mesh('ptND', points, tetrahedra)`, MESH = kuhn) and checked the same way; the script
stops if neither passes.

Measured per case and repeat (one CSV row): the wall time of each process (time.perf_counter
around subprocess.run, so start-up, `import getfem`, mesh, assembly, solve and output included);
the largest nodal displacement difference relative to the largest displacement,
max over nodes ‖u_project − u_GetFEM‖ / max over nodes ‖u_GetFEM‖ (Euclidean norms; nodes
matched by coordinates rounded to 1e-9; a node the project writes more than once, on a subdomain
interface, counts with each of its copies); the total contact force of the foundation on the
body from both (their relative difference); the project's n_A (Hessian multiplications), outer
iterations and solve time from summary.json; GetFEM's Newton iterations and the time of its
`solve` call; the open/stick/slip counts of both (GetFEM's by the project's rule: pressed if
the normal force exceeds 1e-8 of the largest, slip if ‖λ_T‖ ≥ (1 − 1e-4) F λ_N).

Options:
  --exe PATH             the project's executable (default build/feticontact)
  --cases LIST           comma-separated cases F<F>_k<k>, any F and k (default F0.3_k8,
                         F0.3_k12,F0.3_k16,F0.3_k24,F0.1_k12)
  --repeats N            runs of each case with k ≤ 16 (default 3)
  --repeats-large N      runs of each case with k > 16 (default 1)
  --csv PATH             one row per run (default doc/reports/data/against_getfem.csv); rewritten after
                         every run: rows of the chosen cases are replaced, others kept
  --markdown PATH        the table (default doc/reports/data/against_getfem.md): per case the medians
                         of the wall times, their ratio GetFEM / project, the displacement
                         difference (largest over the runs), n_A and the Newton iterations
  --plot PATH            wall time against n, log-log, both codes, ratios annotated
                         (default doc/reports/against_getfem.png)
  --report-only          rebuild the table and the plot from the CSV without running anything

Both processes run with their own defaults on whatever the machine offers (the project with its
threads per rank, GetFEM with its BLAS): the times are indicative of this machine. Standard
library, numpy and matplotlib (the plot); GetFEM's `python3-getfem` for the interpreter that
runs the script (Debian's /usr/bin/python3).
"""
import csv
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from rows import write_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

YOUNG = 2.12e11
POISSON = 0.277
TOP_TRACTION = (2e7, 0.0, -1e8)  # Pa, on z = 1
END_TRACTION = (0.0, 3e7, 0.0)  # Pa, on x = 3
AUGMENTATION = 10.0  # r = 10 E
LARGE_K = 16  # cases with k above it run --repeats-large times

DEFAULT_CASES = ["F0.3_k8", "F0.3_k12", "F0.3_k16", "F0.3_k24", "F0.1_k12"]


def parse_case(name):
    """(F, k) of a case name F<F>_k<k>, or None."""
    match = re.fullmatch(r"F(\d+(?:\.\d+)?)_k([1-9]\d*)", name)
    return (float(match.group(1)), int(match.group(2))) if match else None


FIELDS = ["case", "F", "k", "n", "run", "project_wall_s", "getfem_wall_s", "difference",
          "contact_force_difference", "project_n_A", "project_outer_iterations",
          "project_solve_s", "project_open", "project_stick", "project_slip",
          "getfem_newton_iterations", "getfem_solve_s", "getfem_import_s", "getfem_open",
          "getfem_stick", "getfem_slip", "getfem_mesh"]


def unknowns(k):
    return 3 * (3 * k + 1) * (k + 1) ** 2


# --- GetFEM: the mesh and its check ---------------------------------------------------------

def lattice(k):
    return (np.linspace(0, 3, 3 * k + 1), np.linspace(0, 1, k + 1), np.linspace(0, 1, k + 1))


def kuhn_tetrahedra(k):
    """Points (3 × nodes) and tetrahedra (4 × cells) of the Kuhn split of the box, numbered as
    subdivided_box_kuhn numbers them: x fastest, then y, then z."""
    n = (3 * k, k, k)
    x, y, z = lattice(k)
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
    points = np.vstack([X.ravel(), Y.ravel(), Z.ravel()])
    K, J, I = (a.ravel() for a in np.meshgrid(np.arange(n[2]), np.arange(n[1]),
                                              np.arange(n[0]), indexing="ij"))

    def corner(c):
        """The node of corner c of every cube; corner c is at offsets (c & 1, (c >> 1) & 1,
        (c >> 2) & 1) from the cube's lowest corner."""
        return (I + (c & 1)) + (n[0] + 1) * ((J + ((c >> 1) & 1)) + (n[1] + 1) * (K + (c >> 2)))

    # The six monotone lattice paths from corner 0 to corner 7.
    paths = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]
    return points, np.hstack([np.vstack([corner(c) for c in path]) for path in paths])


def getfem_mesh(gf, k, construction):
    if construction == "regular simplices":
        return gf.Mesh("regular simplices", *lattice(k))
    points, cells = kuhn_tetrahedra(k)
    return gf.Mesh("ptND", points, cells)


def kuhn_split_error(mesh, k):
    """None if the tetrahedra of `mesh` are exactly the Kuhn split of the 3k × k × k box, else
    what is wrong."""
    n = np.array([3 * k, k, k])
    pids, starts = mesh.pid_from_cvid()
    if mesh.nbcvs() != 6 * n.prod():
        return f"{mesh.nbcvs()} convexes instead of {6 * n.prod()}"
    if not np.all(np.diff(starts) == 4):
        return "a convex without exactly four vertices"
    column = np.zeros(mesh.max_pid() + 1, dtype=np.int64)  # pts() has the points of pid()
    column[mesh.pid()] = np.arange(mesh.nbpts())
    coordinates = mesh.pts()[:, column[pids]].T * k
    vertices = np.rint(coordinates).astype(np.int64)
    if np.abs(coordinates - vertices).max() > 1e-9:
        return "a vertex off the lattice"
    vertices = vertices.reshape(-1, 4, 3)
    order = np.argsort(vertices.sum(axis=2), axis=1, kind="stable")
    vertices = np.take_along_axis(vertices, order[:, :, None], axis=1)
    steps = np.diff(vertices, axis=1)  # three steps per tetrahedron
    unit = np.all((steps == 0) | (steps == 1), axis=2) & (steps.sum(axis=2) == 1)
    if not unit.all():
        return "a tetrahedron that is not a monotone lattice path"
    axes = np.argmax(steps, axis=2)
    if np.any(np.sort(axes, axis=1) != [0, 1, 2]):
        return "a path that does not reach the cube's highest corner"
    if np.any(vertices[:, 0] < 0) or np.any(vertices[:, 3] > n):
        return "a tetrahedron outside the box"
    cube = (vertices[:, 0, 0] * n[1] + vertices[:, 0, 1]) * n[2] + vertices[:, 0, 2]
    path = axes[:, 0] * 2 + (axes[:, 1] > axes[:, 2])  # the order of the axes, 0 … 5
    if len(np.unique(cube * 6 + path)) != len(path):
        return "a (cube, path) pair twice"
    return None


def choose_meshes(ks):
    """For every k, the GetFEM mesh construction whose tetrahedra are the Kuhn split."""
    import getfem as gf
    chosen = {}
    for k in ks:
        errors = []
        for construction in ("regular simplices", "kuhn"):
            error = kuhn_split_error(getfem_mesh(gf, k, construction), k)
            if error is None:
                chosen[k] = construction
                break
            errors.append(f"{construction}: {error}")
        else:
            raise SystemExit(f"k = {k}: no GetFEM mesh is the Kuhn split ({'; '.join(errors)})")
        print(f"k = {k}: GetFEM mesh '{chosen[k]}' is the Kuhn split"
              + (f" ({errors[0]})" if errors else ""), flush=True)
    return chosen


# --- GetFEM: the solve (the process of --getfem-run) ----------------------------------------

def getfem_run(k, F, construction, directory):
    """Solve the brick with GetFEM and write nodes.npy (x, y, z, ux, uy, uz per node, 6 × nodes)
    and result.json into `directory`. Units of E: see the module docstring."""
    start = time.perf_counter()
    import getfem as gf
    imported = time.perf_counter()
    mesh = getfem_mesh(gf, k, construction)
    mfu = gf.MeshFem(mesh, 3)
    mfu.set_fem(gf.Fem("FEM_PK(3,1)"))
    mim = gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(1)"))

    CLAMPED, END, CONTACT, TOP = 1, 2, 5, 6
    faces = mesh.outer_faces()
    normals = mesh.normal_of_faces(faces)
    for region, axis, sign in ((CLAMPED, 0, -1), (END, 0, 1), (CONTACT, 2, -1), (TOP, 2, 1)):
        mesh.set_region(region, faces[:, np.abs(normals[axis] - sign) < 1e-8])

    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    # Units of E: Young's modulus 1, stresses and the augmentation parameter divided by E.
    lame_lambda = POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
    lame_mu = 1 / (2 * (1 + POISSON))
    md.add_initialized_data("lambda", [lame_lambda])
    md.add_initialized_data("mu", [lame_mu])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    md.add_initialized_data("top_traction", [t / YOUNG for t in TOP_TRACTION])
    md.add_source_term_brick(mim, "u", "top_traction", TOP)
    md.add_initialized_data("end_traction", [t / YOUNG for t in END_TRACTION])
    md.add_source_term_brick(mim, "u", "end_traction", END)
    md.add_Dirichlet_condition_with_simplification("u", CLAMPED)

    contact_dofs = mfu.dof_on_region(CONTACT)
    n_contact = len(contact_dofs) // 3
    md.add_variable("lambda_n", n_contact)
    md.add_variable("lambda_t", 2 * n_contact)
    md.add_initialized_data("r", [AUGMENTATION])
    md.add_initialized_data("friction_coeff", [F])
    # The foundation z < 0, lifted by 1 m under the clamped nodes of x = 0.
    md.add_nodal_contact_with_rigid_obstacle_brick(
        mim, "u", "lambda_n", "lambda_t", "r", "friction_coeff", CONTACT,
        "z + Heaviside(1e-9 - x)", 1)
    assembled = time.perf_counter()
    iterations, converged = md.solve("max_iter", 100, "max_res", 1e-10, "lsolver", "mumps")
    solved = time.perf_counter()

    dof_nodes = mfu.basic_dof_nodes()
    nodes = dof_nodes[:, 0::3]
    assert np.array_equal(nodes, dof_nodes[:, 1::3]) and np.array_equal(nodes, dof_nodes[:, 2::3])
    u = md.variable("u").reshape(-1, 3).T
    np.save(os.path.join(directory, "nodes.npy"), np.vstack([nodes, u]))

    # The multipliers in the brick's order: one per node of the region, in increasing dof order;
    # λ_N ≤ 0 presses, the tangential frame of the flat obstacle is (e_x, e_y). The force of the
    # foundation on the body is E (λ_T1, λ_T2, −λ_N) summed over the nodes.
    lambda_n = md.variable("lambda_n")
    lambda_t = md.variable("lambda_t").reshape(-1, 2)
    contact_nodes = mfu.basic_dof_nodes(contact_dofs[0::3])
    assert np.allclose(contact_nodes[2], 0)
    pressure = -lambda_n
    tangential = np.hypot(lambda_t[:, 0], lambda_t[:, 1])
    counted = contact_nodes[0] > 1e-9  # the nodes of x = 0 are clamped, not contact nodes
    pressed = pressure > 1e-8 * pressure.max()
    slip = pressed & (tangential >= (1 - 1e-4) * F * pressure)
    result = {
        "newton_iterations": int(iterations), "converged": bool(converged),
        "contact_force": [YOUNG * lambda_t[:, 0].sum(), YOUNG * lambda_t[:, 1].sum(),
                          YOUNG * pressure.sum()],
        "open": int(np.sum(counted & ~pressed)), "stick": int(np.sum(counted & pressed & ~slip)),
        "slip": int(np.sum(counted & slip)),
        "times": {"import": imported - start, "setup": assembled - imported,
                  "solve": solved - assembled, "output": time.perf_counter() - solved},
    }
    with open(os.path.join(directory, "result.json"), "w", encoding="utf-8") as f:
        json.dump(result, f, indent=1)


# --- The runs --------------------------------------------------------------------------------

def run_project(exe, F, k, directory):
    output = os.path.join(directory, "project")
    command = [exe, os.path.join(ROOT, "prm", "brick_contact.prm"),
               "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
               "--set", f"Contact/Zone 1/Friction coefficient={F}",
               "--set", f"Output/Directory={output}"]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    summary_path = os.path.join(output, "summary.json")
    summary = None
    if os.path.exists(summary_path):
        with open(summary_path, encoding="utf-8") as f:
            summary = json.load(f)
    if result.returncode != 0 or not summary or summary.get("converged") is not True:
        raise SystemExit(f"project, F = {F}, k = {k}: exit status {result.returncode}, "
                         f"converged {summary and summary.get('converged')}\n"
                         f"{result.stderr[-2000:]}")
    table = np.loadtxt(os.path.join(output, "displacements.csv"), delimiter=",", skiprows=1,
                       ndmin=2)
    shutil.rmtree(output)
    return wall, summary, table[:, 1:4], table[:, 4:7]


def run_getfem(F, k, construction, directory):
    output = os.path.join(directory, "getfem")
    os.makedirs(output)
    command = [sys.executable, os.path.abspath(__file__), "--getfem-run", str(k), str(F),
               construction, output]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    result_path = os.path.join(output, "result.json")
    if result.returncode != 0 or not os.path.exists(result_path):
        raise SystemExit(f"GetFEM, F = {F}, k = {k}: exit status {result.returncode}\n"
                         f"{result.stderr[-2000:]}")
    with open(result_path, encoding="utf-8") as f:
        summary = json.load(f)
    if not summary["converged"]:
        raise SystemExit(f"GetFEM, F = {F}, k = {k}: Newton did not converge in "
                         f"{summary['newton_iterations']} iterations")
    table = np.load(os.path.join(output, "nodes.npy"))
    shutil.rmtree(output)
    return wall, summary, table[:3].T, table[3:].T


def difference(k, x_project, u_project, x_getfem, u_getfem):
    """max ‖u_project − u_GetFEM‖ / max ‖u_GetFEM‖ over the nodes, matched by coordinates."""
    def key(x):
        return tuple(round(float(c), 9) + 0.0 for c in x)
    index = {key(x): i for i, x in enumerate(x_getfem)}
    n_nodes = (3 * k + 1) * (k + 1) ** 2
    if len(index) != n_nodes or len(u_getfem) != n_nodes:
        raise SystemExit(f"k = {k}: GetFEM wrote {len(u_getfem)} nodes, {len(index)} distinct, "
                         f"instead of {n_nodes}")
    try:
        rows = np.array([index[key(x)] for x in x_project])
    except KeyError as e:
        raise SystemExit(f"k = {k}: the project's node {e} is not a GetFEM node") from None
    if len(set(rows.tolist())) != n_nodes:
        raise SystemExit(f"k = {k}: the project wrote {len(set(rows.tolist()))} distinct nodes "
                         f"instead of {n_nodes}")
    scale = np.linalg.norm(u_getfem, axis=1).max()
    return float(np.linalg.norm(u_project - u_getfem[rows], axis=1).max() / scale)


def measure(exe, case, construction, directory):
    F, k = parse_case(case)
    wall_p, summary, x_p, u_p = run_project(exe, F, k, directory)
    wall_g, result, x_g, u_g = run_getfem(F, k, construction, directory)
    force_p = np.add(summary["contact"]["normal_force"], summary["contact"]["tangential_force"])
    force_g = np.array(result["contact_force"])
    return {"case": case, "F": F, "k": k, "n": unknowns(k),
            "project_wall_s": f"{wall_p:.3f}", "getfem_wall_s": f"{wall_g:.3f}",
            "difference": f"{difference(k, x_p, u_p, x_g, u_g):.3e}",
            "contact_force_difference":
                f"{np.linalg.norm(force_p - force_g) / np.linalg.norm(force_g):.3e}",
            "project_n_A": summary["hessian_multiplications"]["total"],
            "project_outer_iterations": summary.get("outer_iterations", ""),
            "project_solve_s": f"{summary['times']['solve']:.3f}",
            "project_open": summary["contact"]["open"],
            "project_stick": summary["contact"]["stick"],
            "project_slip": summary["contact"]["slip"],
            "getfem_newton_iterations": result["newton_iterations"],
            "getfem_solve_s": f"{result['times']['solve']:.3f}",
            "getfem_import_s": f"{result['times']['import']:.3f}",
            "getfem_open": result["open"], "getfem_stick": result["stick"],
            "getfem_slip": result["slip"], "getfem_mesh": construction}


# --- The table and the plot ------------------------------------------------------------------

def summarize(rows):
    """Per case present in `rows` (F descending, then k): medians and the largest difference."""
    out = []
    for case in sorted({r["case"] for r in rows}, key=lambda c: (-parse_case(c)[0],
                                                                  parse_case(c)[1])):
        runs = [r for r in rows if r["case"] == case]

        def median(key):
            return statistics.median(float(r[key]) for r in runs)

        def counts(code):
            values = {"/".join(str(r[f"{code}_{s}"]) for s in ("open", "stick", "slip"))
                      for r in runs}
            return ", ".join(sorted(values))

        def values(key):
            return ", ".join(sorted({str(r[key]) for r in runs}, key=float))

        F, k = parse_case(case)
        out.append({"case": case, "F": F, "k": k, "n": unknowns(k), "runs": len(runs),
                    "project": median("project_wall_s"), "getfem": median("getfem_wall_s"),
                    "difference": max(float(r["difference"]) for r in runs),
                    "force": max(float(r["contact_force_difference"]) for r in runs),
                    "n_A": values("project_n_A"),
                    "outer": values("project_outer_iterations"),
                    "newton": values("getfem_newton_iterations"),
                    "project_counts": counts("project"), "getfem_counts": counts("getfem"),
                    "getfem_solve": median("getfem_solve_s"),
                    "project_solve": median("project_solve_s")})
    return out


def command_line(rows, paths):
    """The command that reruns the cases of `rows` with the repeats they have."""
    cases = [c["case"] for c in summarize(rows)]
    parts = ["/usr/bin/python3 benchmarks/against_getfem.py"]
    if sorted(cases) != sorted(DEFAULT_CASES):
        parts.append("--cases " + ",".join(cases))
    small = [int(r["run"]) for r in rows if int(r["k"]) <= LARGE_K]
    large = [int(r["run"]) for r in rows if int(r["k"]) > LARGE_K]
    if small and max(small) != 3:
        parts.append(f"--repeats {max(small)}")
    if large and max(large) != 1:
        parts.append(f"--repeats-large {max(large)}")
    for name, (path, default) in paths.items():
        if os.path.abspath(path) != os.path.abspath(default):
            parts.append(f"{name} {os.path.relpath(os.path.abspath(path), ROOT)}")
    return " ".join(parts)


def report(rows, markdown, plot, paths):
    cases = summarize(rows)
    lines = ["| F | k | n | project wall [s] | GetFEM wall [s] | GetFEM / project | "
             "max ‖Δu‖ / max ‖u‖ | contact force Δ | project n_A | project outer iterations | "
             "GetFEM Newton iterations | open/stick/slip project | open/stick/slip GetFEM | "
             "project solve [s] | GetFEM solve [s] | runs |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        lines.append(
            f"| {c['F']} | {c['k']} | {c['n']:,} | {c['project']:.2f} | {c['getfem']:.2f} | "
            f"{c['getfem'] / c['project']:.2f} | {c['difference']:.1e} | {c['force']:.1e} | "
            f"{c['n_A']} | {c['outer']} | {c['newton']} | {c['project_counts']} | "
            f"{c['getfem_counts']} | {c['project_solve']:.2f} | {c['getfem_solve']:.2f} | "
            f"{c['runs']} |")
    text = (f"<!-- written by: {command_line(rows, paths)} -->\n"
            "The brick with Coulomb friction (prm/brick_contact.prm) solved by this project with "
            "its defaults and by GetFEM 5.4 (nodal contact with the rigid obstacle, Alart–Curnier, "
            "Newton with MUMPS) on the same mesh (the Kuhn split of 3k × k × k cubes), each as "
            "its own process: wall times are process wall times (start-up, `import getfem`, "
            "assembly, solve and output included), medians of the runs; `solve` is each "
            "code's own solve phase (summary.json; GetFEM's `Model.solve`). max ‖Δu‖ / max ‖u‖ "
            "is the largest nodal displacement difference relative to the largest displacement, "
            "contact force Δ the relative difference of the total force of the foundation, the "
            "largest over the runs. See the docstring of benchmarks/against_getfem.py.\n\n"
            + "\n".join(lines)
            + f"\n\nReproduce (then `--report-only` rebuilds this table and the plot from the "
              f"CSV):\n\n    {command_line(rows, paths)}\n")
    with open(markdown, "w", encoding="utf-8") as f:
        f.write(text)
    print(text)
    if cases:
        draw(cases, plot)


def draw(cases, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for F, fill in ((0.3, True), (0.1, False)):
        group = [c for c in cases if c["F"] == F]
        if not group:
            continue
        n = [c["n"] for c in group]
        for code, label, colour, marker in (("project", "this project", "tab:blue", "o"),
                                            ("getfem", "GetFEM 5.4", "tab:orange", "s")):
            ax.plot(n, [c[code] for c in group], marker=marker, color=colour,
                    linestyle="-" if len(group) > 1 else "none",
                    markerfacecolor=colour if fill else "none", label=f"{label}, F = {F}")
        for c in group:
            ax.annotate(f"×{c['getfem'] / c['project']:.1f}", (c["n"], c["getfem"]),
                        textcoords="offset points", xytext=(6, 4 if fill else -12), fontsize=9)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.margins(x=0.15, y=0.1)  # room for the annotations
    ax.set_xlabel("unknowns n = 3 (3k+1)(k+1)²")
    ax.set_ylabel("process wall time [s] (median)")
    ax.set_title("Brick with Coulomb friction: this project and GetFEM\n"
                 "(annotated: GetFEM time / project time)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    if sys.argv[1:2] == ["--getfem-run"]:
        if len(sys.argv) != 6:
            raise SystemExit("--getfem-run needs k, F, the mesh construction and a folder")
        getfem_run(int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5])
        return
    arguments(__doc__, ["--exe", "--cases", "--repeats", "--repeats-large", "--csv",
                        "--markdown", "--plot"], ["--report-only"])
    exe = os.path.abspath(option("--exe", os.path.join(ROOT, "build", "feticontact")))
    cases = option("--cases", ",".join(DEFAULT_CASES)).split(",")
    repeats = int(option("--repeats", "3"))
    repeats_large = int(option("--repeats-large", "1"))
    paths = {"--csv": (option("--csv", os.path.join(ROOT, "doc", "reports", "data", "against_getfem.csv")),
                       os.path.join(ROOT, "doc", "reports", "data", "against_getfem.csv")),
             "--markdown": (option("--markdown",
                                   os.path.join(ROOT, "doc", "reports", "data", "against_getfem.md")),
                            os.path.join(ROOT, "doc", "reports", "data", "against_getfem.md")),
             "--plot": (option("--plot", os.path.join(ROOT, "doc", "reports", "against_getfem.png")),
                        os.path.join(ROOT, "doc", "reports", "against_getfem.png"))}
    csv_path, markdown, plot = (p for p, _ in paths.values())
    for name in cases:
        if parse_case(name) is None:
            raise SystemExit(f"case '{name}' is not of the form F<F>_k<k> (e.g. F0.3_k8)")
    if repeats < 1 or repeats_large < 1:
        raise SystemExit("--repeats and --repeats-large must be at least 1")
    report_only = "--report-only" in sys.argv
    if not report_only and not os.access(exe, os.X_OK):
        raise SystemExit(f"{exe} is not an executable (see --exe)")
    rows = []
    if os.path.exists(csv_path):
        with open(csv_path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    elif report_only:
        raise SystemExit(f"{csv_path} does not exist")
    if not report_only:
        meshes = choose_meshes(sorted({parse_case(c)[1] for c in cases}))
        rows = [r for r in rows if r["case"] not in cases]
        with tempfile.TemporaryDirectory() as directory:
            for case in cases:
                k = parse_case(case)[1]
                for repeat in range(repeats_large if k > LARGE_K else repeats):
                    row = measure(exe, case, meshes[k], directory)
                    row["run"] = repeat + 1
                    rows.append(row)
                    print(f"{case:10s} run {repeat + 1}: project {row['project_wall_s']} s "
                          f"(n_A {row['project_n_A']}), GetFEM {row['getfem_wall_s']} s "
                          f"({row['getfem_newton_iterations']} Newton iterations), "
                          f"difference {row['difference']}", flush=True)
                    write_rows(csv_path, FIELDS, rows)
    report(rows, markdown, plot, paths)


if __name__ == "__main__":
    main()
