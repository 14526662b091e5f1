#!/usr/bin/env python3
"""Regression test of one scene in deal.II's form: run, reduce to a short text, compare.

  regression.py EXE PRM OUTDIR REFERENCE [--np N] [--set PATH=VALUE]... [--schema SCHEMA]
  regression.py check-schema SUMMARY_JSON [SCHEMA]
  regression.py parameters EXE REFERENCE

The first form runs EXE on PRM (with mpirun -np N for N > 1) into OUTDIR, with the displacement
CSV switched on, and requires exit status 0. It checks OUTDIR/summary.json against SCHEMA
(default: summary_schema.json beside this script), writes the run's quantities to OUTDIR.output
(one `name value` per line, see write_output) and compares that file with REFERENCE by numdiff:

  - counts (iterations, Hessian multiplications n_A, sizes, open/stick/slip) must be equal;
  - floating-point values (forces, displacements, lengths) may differ by NUMDIFF_RELATIVE.

With the environment variable FETICONTACT_REGENERATE=1 the output is copied to REFERENCE instead
of compared (the run and the schema check are still made): after a change that is meant to
change the results, `FETICONTACT_REGENERATE=1 ctest -L regression` and review `git diff`.

The second form only checks a summary.json against the schema. The third compares the output
of `EXE --print-parameters` with REFERENCE (doc/parameters.prm) line by line, trailing
whitespace ignored, and on a difference shows it and says how to regenerate the file.
Standard library only (numdiff is a program, tools/install_dependencies.sh installs it).
"""
import csv
import difflib
import json
import math
import os
import shutil
import subprocess
import sys

# run_case.py beside this file, imported without leaving a __pycache__ in the source tree.
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_case import load_summary, run  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCHEMA = os.path.join(HERE, "summary_schema.json")

# numdiff's tolerance for the floating-point values, relative. feticontact is deterministic to
# the last bit for one build (any number of threads or ranks: the scene tests compare
# displacements with tolerance 0), so the reference's own build reproduces every digit. Another
# compiler, BLAS or CHOLMOD build rounds differently; as long as the iteration counts stay the
# same (they are compared exactly) that moves the forces and displacements by rounding
# amplified by the conditioning of the solves, measured far below 1e-8 of the values, while a
# change of the method moves them by the solver tolerances (1e-6 to 1e-10) or more. A count
# changed by one differs by at least 1/count > 1e-8 relatively for any count below 1e8, so the
# same relative tolerance compares counts exactly; no absolute tolerance is given (numdiff's
# default 0), so that rule holds for every line.
NUMDIFF_RELATIVE = "1e-8"
# Components of forces and displacements smaller than this fraction of the largest of their
# kind (applied force of the scene; largest displacement) are rounding noise (a zero force
# component summed from rounded nodal values, 1e-13 of the loads and less): they are written as
# 0, which numdiff then compares exactly. The real components of the scenes of regression/ lie
# above 2e-4 of the scale.
NOISE = 1e-10


def regenerate():
    return os.environ.get("FETICONTACT_REGENERATE", "") not in ("", "0")


# --- summary.json against the schema ----------------------------------------------------------
TYPES = {
    "bool": lambda v: isinstance(v, bool),
    "int": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "string": lambda v: isinstance(v, str),
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
}


def summary_kind(summary):
    """The kind of run a summary.json describes: 'no_equilibrium' (the solver proved that no
    equilibrium exists), 'contact' (solved with contact nodes), 'no_contact' (a linear solve)."""
    if summary.get("no_equilibrium") is True:
        return "no_equilibrium"
    m_contact = summary.get("m_contact", 0)
    return "contact" if isinstance(m_contact, int) and m_contact > 0 else "no_contact"


def check_value(value, spec, path, kind, errors):
    expected = spec["type"]
    if not TYPES[expected](value):
        errors.append(f"{path}: {type(value).__name__} {json.dumps(value)[:60]}, expected {expected}")
        return
    if expected == "object":
        check_object(value, spec.get("keys", {}), path, kind, errors)
    elif expected == "array":
        if "length" in spec and len(value) != spec["length"]:
            errors.append(f"{path}: {len(value)} entries, expected {spec['length']}")
        for i, item in enumerate(value):
            check_value(item, spec["items"], f"{path}.{i}", kind, errors)


def check_object(obj, keys, path, kind, errors):
    prefix = path + "." if path else ""
    for key in obj:
        if key not in keys:
            errors.append(f"{prefix}{key}: a key the schema does not know")
    for key, spec in keys.items():
        required = spec.get("required", False)
        if isinstance(required, list):
            required = kind in required
        if key in obj:
            check_value(obj[key], spec, prefix + key, kind, errors)
        elif required:
            errors.append(f"{prefix}{key}: missing (required in a summary of kind {kind})")


def check_schema(summary, schema_file):
    with open(schema_file, encoding="utf-8") as f:
        schema = json.load(f)
    errors = []
    kind = summary_kind(summary)
    check_object(summary, schema["keys"], "", kind, errors)
    for e in errors:
        print("  summary.json schema: " + e)
    print(f"  summary.json ({kind}) against {os.path.basename(schema_file)}: "
          f"{'ok' if not errors else 'FAILED'}")
    return not errors


# --- The regression output ---------------------------------------------------------------------
def number(value, scale=None):
    """A value as numdiff reads it: integers as integers, floats in the shortest form that reads
    back to the same double, components below NOISE × scale as 0."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if scale is not None and abs(value) <= NOISE * scale:
        return "0"
    return repr(float(value))


def coordinate(x):
    return "%g" % x


def nearest(rows, target):
    """The row of the vertex nearest to target (the first in file order on a tie)."""
    return min(rows, key=lambda r: sum((r["x"][i] - target[i]) ** 2 for i in range(3)))


def read_rows(path, floats):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in floats:
            r[k] = float(r[k])
    return rows


def write_output(summary, outdir, output_file):
    """The quantities of the run that a change of the method or of the scene would move, none
    that depends on the machine (times, memory, threads, the split of the work among ranks):
      sizes:     n_primal, n_primal_feti, n_subdomains, n_rigid_modes, m_total, m_equality,
                 m_contact, h_min;
      counts:    outer_iterations (MSA, or the CG iterations without contact),
                 smalbe_iterations, hessian_multiplications.* (n_A = .total), mpgp_steps.*;
      contact:   open/stick/slip and the total normal and tangential forces on the bodies
                 (summary.json), per zone of contact.csv its nodes, statuses, Σ λ_N and Σ ‖λ_T‖;
      bodies:    applied, support and contact forces; max |u| and u at the vertices nearest to
                 the upper corner and to the centre of the body's bounding box;
      hertz.*:   the measured radius, peak pressure and force where Verification/Hertz is on."""
    lines = []

    def put(name, value, scale=None):
        lines.append(f"{name} {number(value, scale)}")

    put("converged", summary["converged"])
    for key in ("n_primal", "n_primal_feti", "n_subdomains", "n_rigid_modes", "m_total",
                "m_equality", "m_contact", "h_min", "outer_iterations", "smalbe_iterations"):
        if key in summary:
            put(key, summary[key])
    for key, value in summary["hessian_multiplications"].items():
        put("hessian_multiplications." + key, value)
    for key, value in summary.get("mpgp_steps", {}).items():
        put("mpgp_steps." + key, value)
    if "load_balance" in summary:
        lines.append("load_balance.outcome " + summary["load_balance"]["outcome"])

    bodies = summary["equilibrium"]["bodies"]
    force_scale = max([math.sqrt(sum(c * c for c in b["applied_force"])) for b in bodies] + [0])
    axes = ("x", "y", "z")
    if "contact" in summary:
        c = summary["contact"]
        for key in ("open", "stick", "slip"):
            put("contact." + key, c[key])
        for key in ("normal_force", "tangential_force"):
            for axis, v in zip(axes, c[key]):
                put(f"contact.{key}.{axis}", v, force_scale)
    contact_csv = os.path.join(outdir, "contact.csv")
    if os.path.exists(contact_csv):
        rows = read_rows(contact_csv, ("lambda_N", "lambda_T1", "lambda_T2"))
        for zone in sorted(set(r["zone"] for r in rows), key=int):
            in_zone = [r for r in rows if r["zone"] == zone]
            put(f"zone{zone}.nodes", len(in_zone))
            for status in ("open", "stick", "slip"):
                put(f"zone{zone}.{status}", sum(1 for r in in_zone if r["status"] == status))
            put(f"zone{zone}.sum_lambda_N", math.fsum(r["lambda_N"] for r in in_zone), force_scale)
            put(f"zone{zone}.sum_norm_lambda_T",
                math.fsum(math.hypot(r["lambda_T1"], r["lambda_T2"]) for r in in_zone), force_scale)

    for b in bodies:
        for key in ("applied_force", "support_force", "contact_force"):
            for axis, v in zip(axes, b[key]):
                put(f"body{b['index']}.{key}.{axis}", v, force_scale)
    rows = read_rows(os.path.join(outdir, "displacements.csv"), ("x", "y", "z", "ux", "uy", "uz"))
    for r in rows:
        r["x"] = (r["x"], r["y"], r["z"])
        r["u"] = (r["ux"], r["uy"], r["uz"])
    u_scale = max(math.sqrt(sum(c * c for c in r["u"])) for r in rows)
    for index in sorted(set(r["body"] for r in rows), key=int):
        of_body = [r for r in rows if r["body"] == index]
        name = f"body{int(index)}"
        put(name + ".max_norm_u", max(math.sqrt(sum(c * c for c in r["u"])) for r in of_body))
        low = [min(r["x"][i] for r in of_body) for i in range(3)]
        high = [max(r["x"][i] for r in of_body) for i in range(3)]
        for target in (high, [(a + b) / 2 for a, b in zip(low, high)]):
            r = nearest(of_body, target)
            at = ",".join(coordinate(x) for x in r["x"])
            for axis, v in zip(axes, r["u"]):
                put(f"{name}.u({at}).{axis}", v, u_scale)
    if "hertz" in summary:
        for key in ("a", "p0", "total_normal_force", "nodes_across_a"):
            put("hertz." + key, summary["hertz"][key])
    if "mortar_overlap" in summary:
        # Relative to max |u| already; below 1e-7 (the solver's tolerance: a patch test) as 0.
        for key in ("slave_into_master", "master_into_slave"):
            put("mortar_overlap." + key, summary["mortar_overlap"][key], 1e-7 / NOISE)
    with open(output_file, "w") as f:
        f.write("\n".join(lines) + "\n")


def compare(output_file, reference):
    if not os.path.exists(reference):
        print(f"FAILED: no reference <{reference}>; create it with FETICONTACT_REGENERATE=1")
        return False
    numdiff = shutil.which("numdiff")
    if numdiff is None:
        print("FAILED: numdiff not found (tools/install_dependencies.sh installs it)")
        return False
    cmd = [numdiff, "-q", "-r", NUMDIFF_RELATIVE, "-s", " \t\n", reference, output_file]
    if subprocess.run(cmd).returncode == 0:
        print(f"  {os.path.basename(output_file)} equals {reference} (numdiff -r {NUMDIFF_RELATIVE}): ok")
        return True
    print(f"FAILED: {output_file} differs from {reference} (numdiff -r {NUMDIFF_RELATIVE}):")
    p = subprocess.run([numdiff, "-r", NUMDIFF_RELATIVE, "-s", " \t\n", "-V", reference, output_file],
                       capture_output=True, text=True)
    sys.stdout.write(p.stdout + p.stderr)
    print("If the change is intended, regenerate the reference: FETICONTACT_REGENERATE=1 ctest "
          "-L regression (or this test with -R), and review the difference with git diff.")
    return False


def parameters(exe, reference):
    """--print-parameters against the documented reference, trailing whitespace ignored."""
    p = subprocess.run([exe, "--print-parameters"], capture_output=True, text=True,
                       errors="replace", timeout=60)
    if p.returncode != 0:
        sys.stdout.write(p.stdout + p.stderr)
        print(f"FAILED: {exe} --print-parameters exited with status {p.returncode}")
        return 1
    with open(reference, encoding="utf-8", errors="replace") as f:
        documented = [line.rstrip() for line in f.read().splitlines()]
    printed = [line.rstrip() for line in p.stdout.splitlines()]
    while documented and not documented[-1]:
        documented.pop()
    while printed and not printed[-1]:
        printed.pop()
    if printed == documented:
        print(f"  {exe} --print-parameters equals {reference}: ok")
        return 0
    diff = list(difflib.unified_diff(documented, printed, reference, "--print-parameters",
                                     lineterm=""))
    print("\n".join(diff[:200]) + ("\n..." if len(diff) > 200 else ""))
    print(f"FAILED: {reference} is not the output of --print-parameters (the parameters or their "
          "documentation changed). Regenerate it in the source directory (build/: the build):\n"
          "  build/feticontact --print-parameters > doc/parameters.prm")
    return 1


def main(args):
    if args and args[0] == "check-schema":
        summary = load_summary(args[1])
        return 0 if check_schema(summary, args[2] if len(args) > 2 else DEFAULT_SCHEMA) else 1
    if args and args[0] == "parameters":
        return parameters(args[1], args[2])
    exe, prm, outdir, reference = args[:4]
    np, sets, schema = 1, [], DEFAULT_SCHEMA
    i = 4
    while i < len(args):
        if args[i] == "--np":
            np = int(args[i + 1])
        elif args[i] == "--set":
            sets += ["--set", args[i + 1]]
        elif args[i] == "--schema":
            schema = args[i + 1]
        else:
            raise ValueError(args[i])
        i += 2
    os.makedirs(os.path.dirname(os.path.abspath(outdir)), exist_ok=True)
    p = run(exe, prm, outdir, np, ["--set", "Output/Write displacement csv=true"] + sets)
    if p.returncode != 0:
        print(f"FAILED: exit status {p.returncode} with {np} rank(s)")
        return 1
    summary = load_summary(os.path.join(outdir, "summary.json"))
    ok = check_schema(summary, schema)
    output_file = outdir + ".output"
    write_output(summary, outdir, output_file)
    if regenerate():
        shutil.copyfile(output_file, reference)
        print(f"  FETICONTACT_REGENERATE: wrote {reference}")
        return 0 if ok else 1
    ok &= compare(output_file, reference)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
