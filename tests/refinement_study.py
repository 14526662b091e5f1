#!/usr/bin/env python3
"""A refinement study run by feticontact itself (`Refinement study/Subdivision factors`) on the
Hertz scene, checked from outside:

  refinement_study.py EXE PRM OUTDIR

- exit 0; one complete run per factor in OUTDIR/cycle-N (summary.json converged);
- convergence_table.txt, convergence_table.org and refinement_study.json in OUTDIR, with one row
  per factor, the unknowns growing, and rate columns for the errors of a and p0;
- the Subdivisions of each cycle are those of the file times the factor (parameters.prm);
- a and p0 of every cycle agree with an independent measurement from its contact.csv
  (benchmarks/hertz.py's hertz_fit, to 1e-8), and the error of p0 falls with every cycle.
Standard library only.
"""
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys

FACTORS = [0.75, 1.0, 1.25]


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def main():
    exe, prm, outdir = sys.argv[1:4]
    shutil.rmtree(outdir, ignore_errors=True)
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "benchmarks"))  # hertz.py imports cli.py
    spec = importlib.util.spec_from_file_location(
        "hertz", os.path.join(here, "..", "benchmarks", "hertz.py"))
    hertz = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hertz)

    run = subprocess.run([exe, "--set", "Refinement study/Subdivision factors=" +
                          ", ".join(str(f) for f in FACTORS),
                          "--set", f"Output/Directory={outdir}", "--set", "Output/Write vtu=false",
                          prm], capture_output=True, text=True, timeout=600)
    print(run.stdout[-3000:])
    if run.returncode != 0:
        fail(f"exit status {run.returncode}: {run.stderr}")
    with open(os.path.join(outdir, "refinement_study.json")) as f:
        study = json.load(f)
    if study["factor"] != FACTORS:
        fail(f"factors {study['factor']}")
    if any(b <= a for a, b in zip(study["unknowns"], study["unknowns"][1:])):
        fail(f"unknowns do not grow: {study['unknowns']}")
    with open(os.path.join(outdir, "convergence_table.txt")) as f:
        lines = [line for line in f if line.strip()]
    if len(lines) != 1 + len(FACTORS):
        fail("convergence_table.txt: " + "".join(lines))
    with open(os.path.join(outdir, "convergence_table.org")) as f:
        org = [line for line in f if line.strip()]
    if len(org) != 1 + len(FACTORS) or "p0 error...red.rate.log2" not in org[0]:
        fail("convergence_table.org: " + "".join(org))
    for cycle, factor in enumerate(FACTORS, start=1):
        cycle_dir = os.path.join(outdir, f"cycle-{cycle}")
        with open(os.path.join(cycle_dir, "summary.json")) as f:
            summary = json.load(f)
        if not summary["converged"]:
            fail(f"cycle {cycle} did not converge")
        with open(os.path.join(cycle_dir, "parameters.prm")) as f:
            text = f.read()
        n = round(16 * factor)
        if not re.search(rf"set Subdivisions\s*=\s*{n}, {n}, {n}\b", text):
            fail(f"cycle {cycle}: Subdivisions {n}, {n}, {n} not in parameters.prm")
        rows = hertz.read_contact(cycle_dir)
        p0, a, _ = hertz.hertz_fit([r for r in rows if r["zone"] == 1])
        for key, mine in (("a", a), ("p0", p0)):
            theirs = summary["hertz"][key]
            ok = abs(mine - theirs) <= 1e-8 * abs(mine)
            print(f"cycle {cycle}: {key} = {theirs:.10e}, from contact.csv {mine:.10e} -> "
                  f"{'ok' if ok else 'FAILED'}")
            if not ok:
                fail(f"cycle {cycle}: {key}")
        if abs(study["p0"][cycle - 1] - p0) > 1e-8 * p0:
            fail(f"cycle {cycle}: refinement_study.json p0 {study['p0'][cycle - 1]}")
    errors = study["p0 error"]
    if any(b >= a for a, b in zip(errors, errors[1:])):
        fail(f"the error of p0 does not fall: {errors}")
    print("refinement study: all checks passed")


if __name__ == "__main__":
    main()
