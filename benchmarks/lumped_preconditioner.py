#!/usr/bin/env python3
"""The lumped FETI preconditioner, without contact and with contact (preconditioning in face).

Brick of doc/formulation.md ("The brick benchmark") with subdomains of 8 × 8 × 8 cubes (H/h = 8, TFETI), k = 8a cubes across,
3a × a × a subdomains. For each a, one run without and one with the preconditioner, one after
the other (never two at a time: paired runs on the two cores slow each other):

  - linear: prm/brick.prm (no contact), projected CG, `FETI/Preconditioner = none | lumped`:
    iterations and solve time;
  - contact: prm/kucera_table_2.prm, Algorithm = mpgp, projected cg expansion, Hessian norm
    bound max, `Contact solver/Expert/Preconditioner = none | lumped`, friction coefficients F:
    n_A (Hessian multiplications), SMALBE iterations, MPGP steps, solve time and the time in
    the preconditioner.

Usage: lumped_preconditioner.py [--exe PATH] [--linear-a 1,2,3,4]
       [--friction 0,0.3] [--markdown doc/reports/data/lumped_preconditioner.md]
       [--csv doc/reports/data/lumped_preconditioner.csv]

The executable is copied to a temporary file first, so that a rebuild during the run does not
change it. OPENBLAS_NUM_THREADS=1.
"""
import csv
import os
import shutil
import subprocess
import tempfile

from cli import arguments, option
from scaling import env, read_summary

HERE = os.path.dirname(os.path.abspath(__file__))
PRM = os.path.join(HERE, "..", "prm")
FIELDS = ["problem", "F", "a", "k", "n_subdomains", "n", "m", "preconditioner", "iterations",
          "n_A", "smalbe", "cg", "expansion", "proportioning", "solve", "preconditioner_time",
          "preconditioner_applications", "converged"]


def run(exe, prm, sets):
    with tempfile.TemporaryDirectory() as out:
        command = [exe, *sum((["--set", s] for s in sets), []),
                   "--set", f"Output/Directory={out}", "--set", "Output/Write vtu=false",
                   "--set", "Output/Write displacement csv=false", prm]
        p = subprocess.run(command, capture_output=True, text=True, env=env())
        return read_summary(p, command, out)


def geometry(a):
    k = 8 * a
    return k, [f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
               "Body 1/Decomposition/Method=blocks",
               f"Body 1/Decomposition/Blocks={3 * a}, {a}, {a}",
               "FETI/Dirichlet treatment=total"]


def row(problem, friction, a, k, preconditioner, s):
    steps = s.get("mpgp_steps", {})
    return {"problem": problem, "F": friction, "a": a, "k": k,
            "n_subdomains": s["n_subdomains"], "n": s["n_primal"], "m": s["m_total"],
            "preconditioner": preconditioner, "iterations": s["iterations"],
            "n_A": s.get("hessian_multiplications", {}).get("total", ""),
            "smalbe": s.get("smalbe_iterations", ""), "cg": steps.get("cg", ""),
            "expansion": steps.get("expansion", ""),
            "proportioning": steps.get("proportioning", ""),
            "solve": round(s["times"]["solve"], 3),
            "preconditioner_time": round(s["times"].get("preconditioner", 0), 3),
            "preconditioner_applications": s["times"].get("preconditioner_applications", 0),
            "converged": s["converged"]}


def main():
    arguments(__doc__, ["--exe", "--linear-a", "--contact-a", "--friction", "--markdown",
                        "--csv"])
    exe_source = option("--exe", os.path.join(HERE, "..", "build", "feticontact"))
    linear_a = [int(x) for x in option("--linear-a", "1,2,3,4").split(",") if x]
    contact_a = [int(x) for x in option("--contact-a", "").split(",") if x]
    if contact_a:
        raise SystemExit("--contact-a: preconditioning MPGP in face was removed from the contact "
                         "solver (it lost on every scene: doc/performance.md, \"Defaults\"); "
                         "its earlier tables stay in doc/reports/data/lumped_preconditioner.md")
    frictions = [x for x in option("--friction", "0,0.3").split(",") if x]
    markdown = option("--markdown", os.path.join(HERE, "..", "doc", "reports", "data",
                                                 "lumped_preconditioner.md"))
    csv_path = option("--csv", os.path.join(HERE, "..", "doc", "reports", "data",
                                            "lumped_preconditioner.csv"))
    with tempfile.TemporaryDirectory() as tmp:
        exe = os.path.join(tmp, "feticontact")
        shutil.copy2(exe_source, exe)
        rows = []
        for a in linear_a:
            k, sets = geometry(a)
            for pc in ("none", "lumped"):
                # Without prm/brick.prm's comparison with a monolithic solve: at 10⁶ unknowns
                # it needs 22 GB beside the FETI solver (doc/feti.md).
                s = run(exe, os.path.join(PRM, "brick.prm"),
                        sets + [f"FETI/Preconditioner={pc}",
                                "Verification/Compare with monolithic solve=false"])
                rows.append(row("linear", "", a, k, pc, s))
                print(rows[-1], flush=True)
        for friction in frictions:
            for a in contact_a:
                k, sets = geometry(a)
                sets += [f"Contact/Zone 1/Friction coefficient={friction}",
                         "Contact solver/Algorithm=mpgp",
                         "Contact solver/MPGP/Expansion step=projected cg",
                         "Contact solver/SMALBE/Hessian norm bound=max"]
                for pc in ("none", "lumped"):
                    s = run(exe, os.path.join(PRM, "kucera_table_2.prm"),
                            sets + [f"Contact solver/Expert/Preconditioner={pc}"])
                    rows.append(row("contact", friction, a, k, pc, s))
                    print(rows[-1], flush=True)
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    with open(markdown, "w") as f:
        f.write("# The lumped FETI preconditioner\n\n"
                "Written by `benchmarks/lumped_preconditioner.py` (one run per cell, one at a "
                "time). H/h = 8, TFETI; k cubes across the brick's width.\n\n"
                "## Without contact: projected CG (`FETI/Preconditioner`)\n\n"
                "| k | subdomains | n | m | iterations, none | iterations, lumped | solve [s], none "
                "| solve [s], lumped | of it in the preconditioner [s] |\n"
                "|---|---|---|---|---|---|---|---|---|\n")
        for a in linear_a:
            r0, r1 = [r for r in rows if r["problem"] == "linear" and r["a"] == a]
            f.write(f"| {r0['k']} | {r0['n_subdomains']} | {r0['n']} | {r0['m']} | "
                    f"{r0['iterations']} | {r1['iterations']} | {r0['solve']} | {r1['solve']} | "
                    f"{r1['preconditioner_time']} |\n")
        f.write("\n## Contact: MPGP preconditioned in face (`Contact solver/Expert/Preconditioner`)\n\n"
                "Algorithm = mpgp, Expansion step = projected cg, Hessian norm bound = max.\n\n"
                "| F | k | n_A, none | n_A, lumped | SMALBE, none | SMALBE, lumped | "
                "CG / expansion / proportioning steps, none | the same, lumped | "
                "solve [s], none | solve [s], lumped |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n")
        for friction in frictions:
            for a in contact_a:
                r0, r1 = [r for r in rows if r["problem"] == "contact" and r["a"] == a
                          and r["F"] == friction]
                f.write(f"| {friction} | {r0['k']} | {r0['n_A']} | {r1['n_A']} | "
                        f"{r0['smalbe']} | {r1['smalbe']} | "
                        f"{r0['cg']} / {r0['expansion']} / {r0['proportioning']} | "
                        f"{r1['cg']} / {r1['expansion']} / {r1['proportioning']} | "
                        f"{r0['solve']} | {r1['solve']} |\n")


if __name__ == "__main__":
    main()
