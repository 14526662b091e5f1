#!/usr/bin/env python3
"""Regenerate every table and plot of doc/ by running the benchmark scripts with the arguments
that produced the documented tables (the commands in the reports of doc/reports/ and in
doc/local_solvers.md), in order: short runs first. The tables and CSV files go to
doc/reports/data/, the plots of the reports to doc/reports/.

    /usr/bin/python3 benchmarks/regenerate_doc.py --list
    /usr/bin/python3 benchmarks/regenerate_doc.py --only NAME[,NAME...] [--exe build/feticontact]
        [--dry-run]
    /usr/bin/python3 benchmarks/regenerate_doc.py --all [--exe build/feticontact] [--dry-run]

--list prints the steps with their expected run time on the 2-core machine of doc/performance.md
and the files they write. --only runs the named steps, --all every step (about 15 hours in all;
most of it the accuracy sweep and the local solver comparison). --dry-run prints the commands.
Run from anywhere; the commands run in the repository root. The timed steps assume an otherwise
idle machine; never run two at a time. The steps run with OpenBLAS's AVX2 kernels
(OPENBLAS_CORETYPE=Haswell, unless the variable is set) wherever the CPU has AVX2, as the tests
do: the counts follow the kernels' rounding (step blas_kernels), and the documented counts are
those of the AVX2 kernels. Build first: `cmake --build build -j2` (the local solver
steps need the targets local_solver_benchmark and triangular_solves, the linear solve
monolithic_solve). Standard library only; the steps use /usr/bin/python3 (matplotlib for the
plots, python3-getfem for against_getfem).
"""
import os
import shlex
import subprocess
import sys
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
PY = "/usr/bin/python3"
# The defaults of the contact solver spelt out (the penalty factor is left to the program): the
# setting of the tables at fixed H/h (doc/performance.md, "MPI on this machine").
DEFAULTS = ["--expansion", "projected cg", "--hessian-norm-bound", "max",
            "--inexact-msa-factor", "0.001", "--recursive-gradient-tolerance", "0.1",
            "--arc-scale", "mean diagonal"]


def steps(exe):
    """(name, expected time, files written, [commands]); a command is an argument list."""
    b = "benchmarks/"
    return [
        ("startup", "10 s", "(prints the times)",
         [["sh", "-c", f"for i in 1 2 3 4 5; do /usr/bin/time -f %e {exe} prm/brick.prm "
                       "> /dev/null; done; for i in 1 2 3 4 5; do /usr/bin/time -f %e "
                       f"{exe} --help > /dev/null; done"]]),
        ("threads", "2 min", "doc/reports/data/threads.md",
         [[PY, b + "threads.py", "--exe", exe, "--repeats", "3"]]),
        ("memory_model", "4 min", "doc/reports/data/memory_model.{csv,md}",
         [[PY, b + "memory_model.py", "--exe", exe]]),
        ("subdomain_size", "10 min", "doc/reports/data/subdomain_size.{csv,md}",
         [[PY, b + "subdomain_size.py", "--exe", exe, "--repeats", "1", "--k", "8,16",
           "--edges", "2,3,4,6,8,12", "--metis-edges", "4,8"],
          [PY, b + "subdomain_size.py", "--exe", exe, "--repeats", "1", "--k", "24",
           "--edges", "4,6,8,12", "--metis-edges", "8", "--merge"]]),
        ("against_getfem", "10 min", "doc/reports/data/against_getfem.{csv,md}, doc/reports/against_getfem.png",
         [[PY, b + "against_getfem.py", "--exe", exe]]),
        ("default_counts", "30 min", "doc/reports/data/default_counts.{csv,md}",
         [[PY, b + "default_counts.py", "--exe", exe, "--k", "4,8,12,16,20,24,32,48",
           "--friction", "0.3,0.1"]]),
        ("solver_defaults", "1 h", "doc/reports/data/solver_defaults.{csv,md}",
         [[PY, b + "solver_defaults.py", "--exe", exe]]),
        ("scaling_coarse", "2 min", "doc/reports/data/scaling.{csv,md}",
         [[PY, b + "scaling.py", "--exe", exe, "--a", "", "--paper-k", "",
           "--coarse-a", "1,3,5,7", "--merge"]]),
        ("scaling_linear", "15 min", "doc/reports/data/scaling_linear.csv, doc/reports/data/scaling.md",
         [[PY, b + "scaling.py", "--monolithic", "build/benchmarks/monolithic_solve",
           "--a", "1,2,3,4,5,6", "--linear-only", "--merge"]]),
        ("scaling_mpi", "5 min", "doc/reports/data/scaling_mpi.{csv,md}",
         [[PY, b + "scaling.py", "--exe", exe, "--a", "3,4", "--np", "1,2", "--repeats", "3",
           "--paper-k", "", "--coarse-a", "", "--csv", "doc/reports/data/scaling_mpi.csv",
           "--markdown", "doc/reports/data/scaling_mpi.md", *DEFAULTS]]),
        ("communication", "1 min", "doc/reports/data/communication.{csv,md}",
         [[PY, b + "communication.py", "--exe", exe]]),
        ("blas_kernels", "2 min", "doc/reports/data/blas_kernels.{csv,md}",
         [[PY, b + "blas_kernels.py", "--exe", exe]]),
        ("communication_k32", "2 min", "doc/reports/data/communication_k32.{csv,md}",
         [[PY, b + "communication.py", "--exe", exe, "--k", "32", "--blocks", "8,4,4",
           "--csv", "doc/reports/data/communication_k32.csv",
           "--markdown", "doc/reports/data/communication_k32.md"]]),
        ("weak_scaling", "3 min", "doc/reports/data/weak_scaling.{csv,md}",
         [[PY, b + "weak_scaling.py", "--exe", exe]]),
        ("parallel_model", "5 min", "doc/reports/data/parallel_model.{csv,md}",
         [[PY, b + "parallel_model.py", "--exe", exe,
           "--mpi-costs", "build/benchmarks/mpi_costs"]]),
        ("scaling_k48", "5 min", "doc/reports/data/scaling_k48.{csv,md}",
         [[PY, b + "scaling.py", "--exe", exe, "--a", "6", "--np", "1,2", "--repeats", "1",
           "--paper-k", "", "--coarse-a", "", "--csv", "doc/reports/data/scaling_k48.csv",
           "--markdown", "doc/reports/data/scaling_k48.md", *DEFAULTS]]),
        ("iteration_growth", "20 min", "doc/reports/data/iteration_growth.{csv,md}, doc/reports/iteration_growth.png",
         [[PY, b + "iteration_growth.py", "--exe", exe, "--a", "1,2,3,4,6", "--jobs", "2"],
          [PY, b + "iteration_growth.py", "--plot", "doc/reports/data/iteration_growth.csv",
           "doc/reports/iteration_growth.png"]]),
        ("triangular_solves", "1 min", "(prints one row of the table)",
         [["sh", "-c", "OPENBLAS_NUM_THREADS=1 build/benchmarks/triangular_solves"]]),
        ("local_solvers", "1 h 15 min", "doc/reports/data/local_solvers.csv, doc/local_solvers.png",
         [[PY, b + "local_solvers.py"]]),
        ("hertz", "4 min", "doc/reports/data/hertz.md, doc/reports/data/hertz_profile.csv, doc/reports/hertz_pressure.png",
         [[PY, b + "hertz.py", "--exe", exe],
          [PY, b + "hertz.py", "--plot", "doc/reports/data/hertz_profile.csv", "doc/reports/hertz_pressure.png"]]),
        ("hertz_two_bodies", "15 min",
         "doc/reports/data/hertz_two_bodies.md, doc/reports/data/hertz_two_bodies_profile.csv, "
         "doc/reports/hertz_two_bodies_pressure.png",
         [[PY, b + "hertz.py", "--exe", exe, "--prm", "prm/hertz_two_bodies.prm",
           "--n", "12,16,24,32", "--markdown", "doc/reports/data/hertz_two_bodies.md",
           "--csv", "doc/reports/data/hertz_two_bodies_profile.csv"],
          [PY, b + "hertz.py", "--prm", "prm/hertz_two_bodies.prm", "--plot",
           "doc/reports/data/hertz_two_bodies_profile.csv", "doc/reports/hertz_two_bodies_pressure.png"]]),
        ("cattaneo_mindlin_pair", "15 min",
         "doc/reports/data/cattaneo_mindlin_pair.{csv,md}, doc/reports/cattaneo_mindlin_pair.png",
         [[PY, b + "cattaneo_mindlin.py", "--exe", exe, "--prm", "prm/cattaneo_mindlin_pair.prm",
           "--n", "16,24", "--ratios", "0,0.25,0.5,0.75", "--sliding", "1.2",
           "--csv", "doc/reports/data/cattaneo_mindlin_pair.csv",
           "--markdown", "doc/reports/data/cattaneo_mindlin_pair.md"],
          [PY, b + "cattaneo_mindlin.py", "--prm", "prm/cattaneo_mindlin_pair.prm", "--plot",
           "doc/reports/data/cattaneo_mindlin_pair.csv", "doc/reports/cattaneo_mindlin_pair.png"]]),
        ("coarse_problem", "22 min", "doc/reports/data/coarse_problem.{csv,md}",
         [[PY, b + "coarse_problem.py", "--binary", "build/benchmarks/coarse_problem",
           "--sizes", "4,8,12,16,20,24", "--np", "1,2,4", "--repeats", "3"]]),
        ("patch_test", "1 min", "doc/reports/data/patch_test.md, doc/reports/patch_test.png",
         [[PY, b + "patch_test.py", "--exe", exe]]),
        ("knife_edge", "1 min", "doc/reports/data/knife_edge.md",
         [[PY, b + "knife_edge.py", "--exe", exe]]),
        ("mortar_overlap", "15 min", "doc/reports/data/mortar_overlap.md",
         [[PY, b + "mortar_overlap.py", "--exe", exe, "--levels", "1,2,3"]]),
        ("mortar_cost", "5 min", "doc/reports/data/mortar_cost.{csv,md}",
         [[PY, b + "mortar_cost.py", "--exe", exe,
           "--coupling", "build/benchmarks/mortar_coupling"]]),
        ("cattaneo_mindlin", "5 min", "doc/reports/data/cattaneo_mindlin.{csv,md}, doc/reports/cattaneo_mindlin.png",
         [[PY, b + "cattaneo_mindlin.py", "--exe", exe, "--n", "16"]]),
        ("accuracy_presets", "15 min", "doc/reports/data/accuracy_presets.md",
         [[PY, b + "accuracy_presets.py", "--exe", exe]]),
        ("poisson_locking", "5 min", "doc/reports/data/poisson_locking.md",
         [[PY, b + "poisson_locking.py", "--exe", exe]]),
        ("friction_range", "30 min", "doc/reports/data/friction_range.md",
         [[PY, b + "friction_range.py", "--exe", exe, "--k", "4,8", "--repeats", "3"]]),
        ("accuracy_sweep", "10 h", "doc/reports/data/accuracy_sweep.{csv,md}, doc/reports/accuracy_sweep.png",
         [[PY, b + "accuracy_sweep.py", "--exe", exe, "--k", "8,16,24", "--repeats", "3",
           "--repeats-large", "1"],
          [PY, b + "accuracy_sweep.py", "--plot", "doc/reports/data/accuracy_sweep.csv",
           "doc/reports/accuracy_sweep.png"]]),
        # Tables of doc/contact.md and doc/feti.md (run times not documented).
        ("brick_refinement", "?", "doc/reports/data/brick_refinement.{csv,md}, doc/brick_refinement.png",
         [[PY, b + "brick_refinement.py", "--exe", exe]]),
        ("reference_comparison", "?", "doc/reports/data/reference_comparison.md",
         [[PY, b + "reference_comparison.py", "--exe", exe]]),
        ("feti_verification", "?", "doc/reports/data/feti_verification.md",
         [[PY, b + "feti_verification.py", "--exe", exe]]),
        ("lumped_preconditioner", "?", "doc/reports/data/lumped_preconditioner.{csv,md} (linear rows only)",
         [[PY, b + "lumped_preconditioner.py", "--exe", exe, "--linear-a", "1,2,3,4"]]),
        ("cookbook_figures", "5 min", "the figures of doc/cookbook*.md",
         [[PY, b + "cookbook_figures.py"]] if os.path.exists(
             os.path.join(ROOT, "benchmarks", "cookbook_figures.py")) else []),
    ]


def environment():
    """The environment of the steps: OPENBLAS_CORETYPE=Haswell where the CPU has AVX2 and the
    variable is not set."""
    env = dict(os.environ)
    try:
        with open("/proc/cpuinfo") as f:
            avx2 = " avx2" in f.read()
    except OSError:
        avx2 = False
    if avx2:
        env.setdefault("OPENBLAS_CORETYPE", "Haswell")
    return env


def show(command):
    return " ".join(shlex.quote(c) for c in command)


def main():
    argv = sys.argv[1:]
    if not argv or "--help" in argv or "-h" in argv:
        print(__doc__.strip())
        return
    exe = argv[argv.index("--exe") + 1] if "--exe" in argv else "build/feticontact"
    table = steps(exe)
    names = [name for name, _, _, _ in table]
    if "--list" in argv:
        for name, duration, files, commands in table:
            print(f"{name:22} {duration:>10}  {files}" + ("" if commands else "  (not present)"))
        return
    if "--only" in argv:
        chosen = argv[argv.index("--only") + 1].split(",")
        unknown = [c for c in chosen if c not in names]
        if unknown:
            raise SystemExit(f"unknown step(s) {', '.join(unknown)}; --list shows the steps")
    elif "--all" in argv:
        chosen = names
    else:
        raise SystemExit("give --only NAME, --all or --list (see --help)")
    for name, duration, files, commands in table:
        if name not in chosen:
            continue
        print(f"== {name} (about {duration}; writes {files})", flush=True)
        for command in commands:
            print("$ " + show(command), flush=True)
            if "--dry-run" in argv:
                continue
            start = time.time()
            result = subprocess.run(command, cwd=ROOT, env=environment())
            if result.returncode != 0:
                raise SystemExit(f"{name}: exit status {result.returncode}")
            print(f"   ({time.time() - start:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
