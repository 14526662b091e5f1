#!/usr/bin/env python3
"""FETI against the monolithic solve on the brick without contact (doc/formulation.md, "The brick benchmark").

Runs build/feticontact on prm/brick.prm for k = 4 and 8 with several decompositions, both
Dirichlet treatments and 1, 2, 3 MPI ranks, and writes the table doc/reports/data/feti_verification.md
(n, subdomains, rigid modes, m, PCG iterations, relative difference to the monolithic solve,
interface jump, force imbalance). Usage (from the repository root, after building):

    python3 benchmarks/feti_verification.py [--exe build/feticontact]

Standard library only.
"""
import json
import os
import subprocess
import sys
import tempfile

exe = "build/feticontact"
if "--exe" in sys.argv:
    exe = sys.argv[sys.argv.index("--exe") + 1]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OPENBLAS_NUM_THREADS="1")

decompositions = [
    ("1 subdomain", ["Body 1/Decomposition/Method=blocks", "Body 1/Decomposition/Blocks=1,1,1"]),
    ("3 blocks (the paper's)", ["Body 1/Decomposition/Method=blocks",
                         "Body 1/Decomposition/Blocks=3,1,1"]),
    ("METIS 8", ["Body 1/Decomposition/Method=metis", "Body 1/Decomposition/Number of parts=8"]),
    ("METIS 27", ["Body 1/Decomposition/Method=metis", "Body 1/Decomposition/Number of parts=27"]),
]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for k in (4, 8):
        for name, sets in decompositions:
            for treatment in ("primal", "total"):
                for np in (1, 2, 3):
                    if np > 1 and name != "METIS 8":
                        continue
                    out = os.path.join(tmp, "run")
                    args = [exe, "--set", f"Output/Directory={out}",
                            "--set", f"Body 1/Mesh/Subdivisions={3*k},{k},{k}",
                            "--set", f"FETI/Dirichlet treatment={treatment}",
                            "--set", "Output/Write vtu=false"]
                    for s in sets:
                        args += ["--set", s]
                    args.append("prm/brick.prm")
                    if np > 1:
                        args = ["mpirun", "-np", str(np)] + args
                    subprocess.run(args, check=True, env=env, capture_output=True)
                    with open(os.path.join(out, "summary.json")) as f:
                        s = json.load(f)
                    rows.append((k, name, treatment, np, s))
                    print(k, name, treatment, np, s["monolithic_difference"], flush=True)

lines = ["| k | n | decomposition | Dirichlet | ranks | subdomains | rigid modes | m | PCG iterations "
         "| monolithic difference | interface jump | force imbalance | ‖Gλ − e‖/‖e‖ before restoration |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for k, name, treatment, np, s in rows:
    lines.append(f"| {k} | {s['n_primal']} | {name} | {treatment} | {np} | {s['n_subdomains']} "
                 f"| {s['n_rigid_modes']} | {s['m_total']} | {s['iterations']} "
                 f"| {s['monolithic_difference']:.1e} | {s['interface_jump']:.1e} "
                 f"| {s['equilibrium']['largest_relative_imbalance']:.1e} "
                 f"| {s.get('coarse_residual_before_restoration', 0):.1e} |")
os.makedirs("doc/reports/data", exist_ok=True)
with open("doc/reports/data/feti_verification.md", "w") as f:
    f.write("<!-- written by: python3 benchmarks/feti_verification.py -->\n")
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
