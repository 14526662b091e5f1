#!/usr/bin/env python3
"""Runs feticontact on one parameter file for ctest and checks the outcome.

  run_case.py scene EXE PRM OUTDIR [--np N[,N...]] [--threads N[,N...]] [--set PATH=VALUE]...
      [--expect KEY<VALUE | KEY>VALUE | KEY=VALUE]... [--same-displacements TOL]
      [--reference-displacements CSV TOL] [--alt-set PATH=VALUE]... [--check-contact-vtu]
      [--contact-area ZONE=AREA]... [--alt-scale S] [--same-counts] [--fewer-multiplications]
      [--exact-field "BODY: UX, UY, UZ"]... [--exact-tolerance TOL] [--uniform-pressure ZONE=P TOL]
      [--same-files PATTERN[,PATTERN...]]
  run_case.py bad EXE PRM OUTDIR --message TEXT [--np N] [--set PATH=VALUE]... [--flag OPTION]
      [--no-equilibrium]
  run_case.py file EXE TESTFILE OUTDIR [--fclib-check PATH] [--print]

file: a test file tests/cases/GROUP/NAME.test (the ctest GROUP.NAME, tests/pickup.cmake), whose
header of '# key: value' lines (tests/README.md, "Adding a test") stands for one of the two modes
below, for one run with its exit status and output checked, or for commands; --print shows what
it stands for instead of running it.

scene: the run must exit 0 and summary.json must satisfy every --expect (KEY is a dotted path
into summary.json, e.g. equilibrium.largest_relative_imbalance; a number indexes an array; the
keys are described in doc/summary_json.md). With several ranks (--np 1,2,3) every run is
checked, and with --same-displacements the nodal displacements of all runs must agree to TOL
relative (max norm); --threads runs each rank count once per number of threads
(DEAL_II_NUM_THREADS, the limit of the threads per rank). --alt-set adds one more run with
further overrides, compared the same way (e.g. μ = 0 against Tresca with slip bound 0);
--alt-scale S divides the displacements of that run by S first (the same scene in other units or
with scaled loads). --same-counts requires every run to take the same MSA iterations and Hessian
multiplications; --fewer-multiplications requires the first run to take fewer Hessian
multiplications than the --alt-set run (an option that must save work against the setting it
replaces). --same-files requires the files of the output folder that match the patterns
(fnmatch, e.g. contact_surface*) to be the same, names and bytes, in the runs with --np and
--threads (the --alt-set run excepted): written by the ranks of their own subdomains, they must
not depend on how many ranks there are.
--exact-field gives the exact displacement of body BODY (1, 2, …) as three Python expressions in
x, y, z (e.g. a patch test's linear field); every node of every body named must have it to
--exact-tolerance (default 1e-8) relative to the largest exact displacement (max norm).
--uniform-pressure requires the pressure λ_N / D_kk of every contact node of ZONE (contact.csv)
to be P to TOL relative.
bad: the run must exit with status 1 (no signal, within BAD_INPUT_TIME_LIMIT), print TEXT
(case-insensitive) on stderr, and leave nothing that looks like a result (summary.json, VTU,
PVD, CSV) in OUTDIR. With --no-equilibrium the input is valid but the solver proves that no
equilibrium exists: exit status 4 within TIME_LIMIT, TEXT on stderr, summary.json with
"converged": false and "no_equilibrium": true, and besides it only the iteration history
(history.csv): no displacement, contact or VTU files.
The regression tests (regression.py) use run() and load_summary() of this file.
Standard library only, so that any python3 runs it.
"""
import csv
import json
import os
import re
import shlex
import shutil
import subprocess
import sys

TIME_LIMIT = 600
# Refusing bad input is a matter of parsing and checking, never of solving.
BAD_INPUT_TIME_LIMIT = 60
# Files that look like a result: a refused run may leave only log.txt and the parameters it read.
RESULT_SUFFIXES = (".json", ".vtu", ".pvtu", ".pvd", ".csv")


def run(exe, prm, outdir, np, extra=(), time_limit=TIME_LIMIT, threads=None):
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    cmd = [exe, "--set", "Output/Directory=" + outdir, *extra, prm]
    if np > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(np)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    if threads is not None:
        env["DEAL_II_NUM_THREADS"] = str(threads)
    print("$", ("DEAL_II_NUM_THREADS=%s " % threads if threads else "") + " ".join(cmd), flush=True)
    # The log echoes names as given, which need not be UTF-8; summary.json must be.
    p = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=time_limit,
                       env=env)
    sys.stdout.write(p.stdout)
    sys.stderr.write(p.stderr)
    return p


def unique_keys(pairs):
    """object_pairs_hook of json.load: a key given twice is an error (a reader would drop one)."""
    keys = [k for k, _ in pairs]
    duplicates = sorted(set(k for k in keys if keys.count(k) > 1))
    if duplicates:
        raise ValueError("summary.json: duplicate keys %s" % duplicates)
    return dict(pairs)


def load_summary(path):
    """summary.json, parsed strictly: UTF-8, valid JSON, unique keys in every object."""
    with open(path, encoding="utf-8") as f:
        return json.load(f, object_pairs_hook=unique_keys)


def lookup(summary, path):
    value = summary
    for key in path.split("."):
        if isinstance(value, list) and key.isdigit() and int(key) < len(value):
            value = value[int(key)]
        elif isinstance(value, dict) and key in value:
            value = value[key]
        else:
            raise KeyError(path)
    return value


def check_expectation(summary, expectation):
    for op in ("<=", ">=", "<", ">", "="):
        if op in expectation:
            key, target = expectation.split(op, 1)
            break
    else:
        raise ValueError("bad expectation " + expectation)
    value = lookup(summary, key.strip())
    target = target.strip()
    if target in ("true", "false"):
        ok = value == (target == "true")
    elif isinstance(value, str):
        ok = op == "=" and value == target
    else:
        t = float(target)
        v = float(value)
        ok = {"<": v < t, ">": v > t, "<=": v <= t, ">=": v >= t, "=": v == t}[op]
    print(f"  check {key.strip()} {op} {target}: value {value} -> {'ok' if ok else 'FAILED'}")
    return ok


def read_displacements(path):
    """The displacements of displacements.csv by body and position (the file's rows are by
    subdomain, which differs between decompositions; a run in other units has its positions
    scaled, which keeps their order)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    rows.sort(key=lambda r: (int(r.get("body", 0)),) + tuple(float(r[k]) for k in "xyz"))
    return [[float(r[k]) for k in ("ux", "uy", "uz")] for r in rows]


def compare_with_reference(ours_file, reference_file, tol):
    """Nodal displacements against a reference CSV (x, y, z, ux, uy, uz), matched by position."""
    def load(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
        return {(round(float(r["x"]), 9), round(float(r["y"]), 9), round(float(r["z"]), 9)):
                [float(r[k]) for k in ("ux", "uy", "uz")] for r in rows}
    ours, ref = load(ours_file), load(reference_file)
    if set(ours) != set(ref):
        print("  FAILED: the nodes differ from the reference's")
        return False
    scale = max(abs(c) for u in ref.values() for c in u)
    diff = max(abs(a - b) for p in ref for a, b in zip(ours[p], ref[p]))
    good = diff <= tol * scale
    print(f"  against {reference_file}: max |u - u_ref| / max |u_ref| = {diff / scale:.3e}"
          f" (tolerance {tol:g}) -> {'ok' if good else 'FAILED'}")
    return good


def check_contact_vtu(directory, csv_name="contact.csv"):
    """contact_surface.pvd points to contact_surface.pvtu, whose pieces are the folder's
    contact_surface_NNNN.vtu, parse, declare the fields of the record and have one value (or
    vector) per point. A point of several pieces has the same values in each and is its own
    (vtkGhostType 0) in exactly one; the contact nodes among the own points are those of
    contact.csv (matched by zone and position, with the same normal forces), so sums over the
    own points equal the file's."""
    import glob
    import xml.etree.ElementTree as ET
    pvd = ET.parse(os.path.join(directory, "contact_surface.pvd")).getroot()
    ok = [d.get("file") for d in pvd.iter("DataSet")] == ["contact_surface.pvtu"]
    record = ET.parse(os.path.join(directory, "contact_surface.pvtu")).getroot()
    declared = [a.get("Name") for a in record.find("PUnstructuredGrid/PPointData")]
    sources = [p.get("Source") for p in record.iter("Piece")]
    on_disk = sorted(os.path.basename(p)
                     for p in glob.glob(os.path.join(directory, "contact_surface_*.vtu")))
    ok &= len(sources) > 0 and sorted(sources) == on_disk
    values, own, n_points, n_cells = {}, {}, 0, 0
    for source in sources:
        piece = ET.parse(os.path.join(directory, source)).getroot().find("UnstructuredGrid/Piece")
        points, cells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))
        n_points, n_cells = n_points + points, n_cells + cells
        ok &= points > 0 and cells > 0
        xyz = [float(v) for v in piece.find("Points/DataArray").text.split()]
        arrays = {a.get("Name"): [float(v) for v in a.text.split()]
                  for a in piece.find("PointData").findall("DataArray")}
        ok &= list(arrays) == declared
        for name, array in arrays.items():
            components = 3 if name in ("tangential_force", "contact_force", "slip") else 1
            ok &= len(array) == components * points
        for p in range(points):
            key = (int(arrays["zone"][p]),) + tuple(round(c, 6) for c in xyz[3 * p:3 * p + 3])
            value = (arrays["status"][p], arrays["normal_force"][p])
            ok &= values.setdefault(key, value) == value
            own[key] = own.get(key, 0) + (arrays["vtkGhostType"][p] == 0)
    ok &= all(n == 1 for n in own.values())
    with open(os.path.join(directory, csv_name)) as f:
        rows = list(csv.DictReader(f))
    from_csv = {(int(r["zone"]),) + tuple(round(float(r[c]), 6) for c in "xyz"): float(r["lambda_N"])
                for r in rows}
    nodes = {k: v[1] for k, v in values.items() if v[0] >= 0}
    scale = max(abs(v) for v in from_csv.values()) or 1
    ok &= len(from_csv) == len(rows) and set(from_csv) == set(nodes) and all(
        abs(from_csv[k] - nodes[k]) <= 1e-9 * scale for k in nodes)
    print(f"  contact_surface.pvtu: {len(sources)} piece(s), {n_points} points ({len(own)} own), "
          f"{n_cells} triangles, fields {', '.join(declared)}; every point own in one piece, "
          f"normal forces as in contact.csv -> {'ok' if ok else 'FAILED'}")
    return ok


def check_exact_field(path, fields, tol):
    """Every node of the bodies in FIELDS ({body: (ux, uy, uz) expressions}) against the exact
    displacement, relative to the largest exact displacement."""
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if int(r["body"]) in fields]
    scale, diff = 0.0, 0.0
    for r in rows:
        where = {"x": float(r["x"]), "y": float(r["y"]), "z": float(r["z"])}
        exact = [eval(e, {"__builtins__": {}}, where) for e in fields[int(r["body"])]]
        scale = max(scale, *(abs(c) for c in exact))
        diff = max(diff, *(abs(float(r[k]) - c) for k, c in zip(("ux", "uy", "uz"), exact)))
    good = bool(rows) and scale > 0 and diff <= tol * scale
    print(f"  exact field of bodies {sorted(fields)} on {len(rows)} nodes: max |u - u_exact| /"
          f" max |u_exact| = {diff / max(scale, 1e-300):.3e} (tolerance {tol:g})"
          f" -> {'ok' if good else 'FAILED'}")
    return good


def check_uniform_pressure(directory, zone, pressure, tol):
    """The pressure of every contact node of ZONE in contact.csv is PRESSURE to TOL relative."""
    with open(os.path.join(directory, "contact.csv")) as f:
        values = [float(r["pressure"]) for r in csv.DictReader(f) if r["zone"] == zone]
    diff = max((abs(v - pressure) for v in values), default=float("inf"))
    good = bool(values) and diff <= tol * abs(pressure)
    print(f"  zone {zone}: {len(values)} nodal pressures within {diff / abs(pressure):.3e} of"
          f" {pressure:g} (tolerance {tol:g}) -> {'ok' if good else 'FAILED'}")
    return good


def read_matching_files(directory, patterns):
    """{name: bytes} of the files in DIRECTORY whose names match one of the fnmatch PATTERNS."""
    import fnmatch
    found = {}
    for name in sorted(os.listdir(directory)):
        if any(fnmatch.fnmatch(name, p) for p in patterns):
            with open(os.path.join(directory, name), "rb") as f:
                found[name] = f.read()
    return found


def check_contact_area(directory, zone, area):
    """The areas lumped at the contact nodes of ZONE add up to the area of its surface, and
    pressure × area = λ_N for every node (contact.csv)."""
    with open(os.path.join(directory, "contact.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["zone"] == zone]
    total = sum(float(r["area"]) for r in rows)
    consistent = all(abs(float(r["pressure"]) * float(r["area"]) - float(r["lambda_N"]))
                     <= 1e-9 * max(abs(float(r["lambda_N"])), 1e-300) for r in rows)
    good = bool(rows) and abs(total - area) <= 1e-12 * area and consistent
    print(f"  zone {zone}: lumped areas add up to {total:.15g} (surface {area:g}), pressure × area"
          f" = λ_N: {consistent} -> {'ok' if good else 'FAILED'}")
    return good


def scene(args):
    exe, prm, outdir = args[:3]
    nps, expectations, same_tol, sets, reference, alt_sets = [1], [], None, [], None, []
    threads = [None]
    check_vtu, areas, alt_scale, same_counts, counts = False, [], 1.0, False, []
    fewer, exact_fields, exact_tol, pressures = False, {}, 1e-8, []
    same_files, files = [], []
    i = 3
    while i < len(args):
        if args[i] == "--set":
            sets += ["--set", args[i + 1]]
        elif args[i] == "--np":
            nps = [int(n) for n in args[i + 1].split(",")]
        elif args[i] == "--threads":
            threads = [int(n) for n in args[i + 1].split(",")]
        elif args[i] == "--expect":
            expectations.append(args[i + 1])
        elif args[i] == "--check-contact-vtu":
            check_vtu = True
            i -= 1
        elif args[i] == "--contact-area":
            zone, area = args[i + 1].split("=")
            areas.append((zone, float(area)))
        elif args[i] == "--alt-scale":
            alt_scale = float(args[i + 1])
        elif args[i] == "--same-counts":
            same_counts = True
            i -= 1
        elif args[i] == "--fewer-multiplications":
            fewer = True
            i -= 1
        elif args[i] == "--alt-set":
            alt_sets += ["--set", args[i + 1]]
        elif args[i] == "--same-files":
            same_files = args[i + 1].split(",")
        elif args[i] == "--exact-field":
            body, expressions = args[i + 1].split(":")
            exact_fields[int(body)] = [e.strip() for e in expressions.split(",")]
        elif args[i] == "--exact-tolerance":
            exact_tol = float(args[i + 1])
        elif args[i] == "--uniform-pressure":
            zone, value = args[i + 1].split("=")
            pressures.append((zone, float(value), float(args[i + 2])))
            i += 1
        elif args[i] == "--same-displacements":
            same_tol = float(args[i + 1])
        elif args[i] == "--reference-displacements":
            reference = (args[i + 1], float(args[i + 2]))
            i += 1
        else:
            raise ValueError(args[i])
        i += 2
    ok = True
    displacements = []
    # With --alt-set, a second run with those entries overridden too (same ranks as the first).
    runs = [(np, t, []) for np in nps for t in threads]
    runs += [(nps[0], threads[0], alt_sets)] if alt_sets else []
    for run_index, (np, t, more) in enumerate(runs):
        d = outdir + (f"_run{run_index}" if len(runs) > 1 else "")
        want_csv = same_tol is not None or reference is not None or bool(exact_fields)
        extra = sets + more + (["--set", "Output/Write displacement csv=true"] if want_csv else [])
        p = run(exe, prm, d, np, extra, threads=t)
        if p.returncode != 0:
            print(f"FAILED: exit status {p.returncode} with {np} rank(s)")
            return 1
        summary = load_summary(os.path.join(d, "summary.json"))
        ok &= check_expectation(summary, "converged=true")
        for e in expectations:
            ok &= check_expectation(summary, e)
        counts.append((summary["outer_iterations"], summary["hessian_multiplications"]["total"]))
        if same_tol is not None:
            u = read_displacements(os.path.join(d, "displacements.csv"))
            if more and alt_scale != 1.0:
                u = [[c / alt_scale for c in row] for row in u]
            displacements.append(u)
        if check_vtu:
            ok &= check_contact_vtu(d)
        if same_files and not more:
            files.append(read_matching_files(d, same_files))
        for zone, area in areas:
            ok &= check_contact_area(d, zone, area)
        if reference is not None:
            ok &= compare_with_reference(os.path.join(d, "displacements.csv"), *reference)
        if exact_fields:
            ok &= check_exact_field(os.path.join(d, "displacements.csv"), exact_fields, exact_tol)
        for zone, value, tol in pressures:
            ok &= check_uniform_pressure(d, zone, value, tol)
    import fnmatch
    for pattern in same_files if files else []:
        if not any(fnmatch.fnmatch(name, pattern) for name in files[0]):
            print(f"  FAILED: no file matches {pattern}")
            ok = False
    for (np, t, more), other in zip(runs[1:], files[1:]):
        good = other == files[0] and len(files[0]) > 0
        print(f"  files {', '.join(same_files)}: {len(files[0])} with -np {nps[0]}, "
              f"{'the same' if other == files[0] else 'different'} with -np {np}"
              + (f", {t} thread(s)" if t else "") + f" -> {'ok' if good else 'FAILED'}")
        ok &= good
    if same_tol is not None:
        ref = displacements[0]
        scale = max(abs(c) for row in ref for c in row)
        for (np, t, more), other in zip(runs[1:], displacements[1:]):
            diff = max(abs(a - b) for ra, rb in zip(ref, other) for a, b in zip(ra, rb))
            good = len(other) == len(ref) and diff <= same_tol * scale
            what = " ".join(more[1::2]) if more else f"-np {np}" + (f", {t} thread(s)" if t else "")
            print(f"  {what} against the first run: max difference {diff / scale:.3e} relative"
                  f" -> {'ok' if good else 'FAILED'}")
            ok &= good
    if same_counts:
        good = all(c == counts[0] for c in counts)
        print(f"  (MSA iterations, Hessian multiplications) of the runs: {counts}"
              f" -> {'ok' if good else 'FAILED'}")
        ok &= good
    if fewer:
        good = bool(alt_sets) and counts[0][1] < counts[-1][1]
        print(f"  Hessian multiplications: {counts[0][1]} against {counts[-1][1]} with"
              f" {' '.join(alt_sets[1::2])} -> {'ok' if good else 'FAILED'}")
        ok &= good
    return 0 if ok else 1


def bad(args):
    exe, prm, outdir = args[:3]
    message, np, sets = None, 1, []
    no_equilibrium = "--no-equilibrium" in args
    args = [a for a in args if a != "--no-equilibrium"]
    i = 3
    while i < len(args):
        if args[i] == "--set":
            sets += ["--set", args[i + 1]]
        elif args[i] == "--flag":
            sets.append(args[i + 1])
        elif args[i] == "--message":
            message = args[i + 1]
        elif args[i] == "--np":
            np = int(args[i + 1])
        i += 2
    limit, status = (TIME_LIMIT, 4) if no_equilibrium else (BAD_INPUT_TIME_LIMIT, 1)
    try:
        p = run(exe, prm, outdir, np, sets, limit)
    except subprocess.TimeoutExpired:
        print(f"FAILED: no answer within {limit} s")
        return 1
    ok = True
    if p.returncode != status:
        print(f"FAILED: exit status {p.returncode}, expected {status} (a negative status is a "
              "signal)")
        ok = False
    allowed = ()
    if no_equilibrium:
        allowed = ("summary.json", "history.csv")
        try:
            summary = load_summary(os.path.join(outdir, "summary.json"))
            if summary.get("converged") is not False or summary.get("no_equilibrium") is not True:
                print("FAILED: summary.json does not say converged = false, no_equilibrium = true")
                ok = False
        except (OSError, ValueError) as e:
            print(f"FAILED: no readable summary.json ({e})")
            ok = False
    if message.lower() not in p.stderr.lower():
        print(f"FAILED: stderr does not name the cause <{message}>")
        ok = False
    results = [os.path.join(d, f) for d, _, files in os.walk(outdir) for f in files
               if f.endswith(RESULT_SUFFIXES) and f not in allowed] if os.path.isdir(outdir) else []
    if results:
        print("FAILED: files that look like a result were written: " + ", ".join(results))
        ok = False
    print("ok" if ok else "")
    return 0 if ok else 1



# --- Tests as files: tests/cases/GROUP/NAME.test, run by `run_case.py file EXE FILE OUTDIR`.
# The header language is described in tests/README.md ("Adding a test").
# Keys whose value is passed on as an option of scene() or bad(), in the order of the file.
OPTIONS = {"set": "--set", "alt-set": "--alt-set", "expect": "--expect", "mpi": "--np",
           "threads": "--threads", "same-displacements": "--same-displacements",
           "same-files": "--same-files", "contact-area": "--contact-area",
           "alt-scale": "--alt-scale", "exact-field": "--exact-field",
           "exact-tolerance": "--exact-tolerance", "flag": "--flag",
           "reference-displacements": "--reference-displacements",
           "uniform-pressure": "--uniform-pressure"}
# Values of two words; the first of reference-displacements is relative to the source folder.
TWO_WORDS = {"reference-displacements", "uniform-pressure"}
FLAGS = {"same-counts": "--same-counts", "check-contact-vtu": "--check-contact-vtu",
         "fewer-multiplications": "--fewer-multiplications"}
CHECKS = {"prm", "message", "exit", "output", "output-regex", "output-if-nonzero", "time-limit",
          "command", "then"}
# Test properties, read by tests/pickup.cmake.
PROPERTIES = {"labels", "timeout", "skip-exit", "run-serial", "fixtures-setup",
              "fixtures-required", "requires"}
KEYS = set(OPTIONS) | set(FLAGS) | CHECKS | PROPERTIES


def read_header(path):
    """The directives of a test file in order: its leading '#' lines of the form '# key: value'
    (or '# flag') with a known key; any other '#' line is a comment. A value is the rest of the
    line without outer spaces, unless it is written in double quotes."""
    directives = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("#"):
                break
            text = line[1:].strip()
            if text in FLAGS:
                directives.append((text, None))
                continue
            key, colon, value = text.partition(":")
            if colon and key in KEYS:
                value = value.strip()
                if len(value) >= 2 and value[0] == value[-1] == '"':
                    value = value[1:-1]
                directives.append((key, value))
    return directives


def test_file_plan(exe, path, outdir, fclib_check=None):
    """What a test file stands for: (kind, argv, checks). kind 'scene' or 'bad': argv is the
    argument list of scene() or bad(); 'run': the command line of one run of the executable;
    'command': the list of the file's commands."""
    tests = os.path.dirname(os.path.abspath(__file__))
    places = {"EXE": exe, "OUT": outdir, "SOURCE_DIR": os.path.dirname(tests),
              "PYTHON": sys.executable, "OUTPUTS": os.path.dirname(os.path.dirname(outdir)),
              "BINARY_DIR": os.path.dirname(os.path.dirname(os.path.dirname(outdir))),
              "FCLIB_CHECK": fclib_check or "fclib_check"}

    def expand(value):
        for name, replacement in places.items():
            value = value.replace("@" + name + "@", replacement)
        return value

    directives = read_header(path)
    checks = {k: [expand(v) for key, v in directives if key == k] for k in CHECKS}
    if checks["command"]:
        commands = []
        for value in checks["command"]:
            words = shlex.split(value)
            if "@FCLIB_FLAG@" in words:
                words.remove("@FCLIB_FLAG@")
                words += ["--fclib"] if fclib_check else []
            commands.append([expand(w) for w in words])
        return "command", commands, checks
    prm = os.path.join(places["SOURCE_DIR"], checks["prm"][0])
    options = []
    for key, value in directives:
        if key in FLAGS:
            options.append(FLAGS[key])
        elif key in TWO_WORDS:
            first, second = expand(value).split()
            if key == "reference-displacements":
                first = os.path.join(places["SOURCE_DIR"], first)
            options += [OPTIONS[key], first, second]
        elif key in OPTIONS:
            options += [OPTIONS[key], value.replace(" ", "") if key == "mpi" else expand(value)]
    status = checks["exit"][0] if checks["exit"] else None
    if checks["message"]:
        if status not in (None, "1", "4"):
            raise ValueError(f"{path}: a refused input exits with status 1 or 4, not {status}")
        options += ["--message", checks["message"][0]] + (["--no-equilibrium"] if status == "4"
                                                          else [])
        return "bad", [exe, prm, outdir] + options, checks
    if status is not None or checks["output"]:
        sets = [(k, v) for k, v in directives if k in OPTIONS or k in FLAGS]
        if any(k not in ("set", "expect") for k, _ in sets):
            raise ValueError(f"{path}: a run with 'exit' takes 'set' and 'expect', no other option")
        sets = [a for k, v in sets if k == "set" for a in ("--set", expand(v))]
        return "run", [exe, "--set", "Output/Directory=" + outdir] + sets + [prm], checks
    return "scene", [exe, prm, outdir] + options, checks


def exit_status_ok(status, allowed):
    """allowed: 'any', 'nonzero' or numbers separated by commas (default 0)."""
    allowed = (allowed or "0").replace(" ", "")
    if allowed == "any":
        return True
    if allowed == "nonzero":
        return status != 0
    return str(status) in allowed.split(",")


def run_checked(kind, argv, checks, outdir):
    """A 'run' or 'command' test: the commands in order (each but the last must exit 0), then the
    exit status of the last, the texts its output must contain, summary.json (for 'run'), and
    'then' commands, which must exit 0."""
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    os.makedirs(os.path.dirname(outdir), exist_ok=True)
    limit = float(checks["time-limit"][0]) if checks["time-limit"] else None
    commands = argv if kind == "command" else [argv]
    ok = True
    for i, cmd in enumerate(commands):
        print("$", shlex.join(cmd), flush=True)
        try:
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               errors="replace", timeout=limit)
        except subprocess.TimeoutExpired:
            print(f"FAILED: no answer within {limit:g} s")
            return 1
        sys.stdout.write(p.stdout)
        last = i == len(commands) - 1
        if not last and p.returncode != 0:
            print(f"FAILED: exit status {p.returncode}")
            return p.returncode
    skip = checks.get("skip-exit")
    if skip and str(p.returncode) == skip:
        return p.returncode
    if not exit_status_ok(p.returncode, checks["exit"][0] if checks["exit"] else None):
        print(f"FAILED: exit status {p.returncode}, expected {checks['exit'] or ['0']}")
        ok = False
    for text in checks["output"] + (checks["output-if-nonzero"] if p.returncode else []):
        good = text in p.stdout
        print(f"  output contains <{text}> -> {'ok' if good else 'FAILED'}")
        ok &= good
    for pattern in checks["output-regex"]:
        good = re.search(pattern, p.stdout) is not None
        print(f"  output matches <{pattern}> -> {'ok' if good else 'FAILED'}")
        ok &= good
    expectations = [v for k, v in read_header(checks["file"]) if k == "expect"]
    if kind == "run" and expectations:
        try:
            summary = load_summary(os.path.join(outdir, "summary.json"))
            for e in expectations:
                ok &= check_expectation(summary, e)
        except (OSError, ValueError, KeyError) as e:
            print(f"FAILED: summary.json ({e})")
            ok = False
    for value in checks["then"] if ok else []:
        cmd = shlex.split(value)
        print("$", shlex.join(cmd), flush=True)
        q = subprocess.run(cmd)
        if q.returncode != 0:
            print(f"FAILED: exit status {q.returncode}")
            ok = False
    print("ok" if ok else "")
    return 0 if ok else 1


def test_file(args):
    """run_case.py file EXE FILE OUTDIR [--fclib-check PATH] [--print]"""
    exe, path, outdir = args[:3]
    fclib_check = args[args.index("--fclib-check") + 1] if "--fclib-check" in args else None
    kind, argv, checks = test_file_plan(exe, path, outdir, fclib_check)
    if "--print" in args:
        print(json.dumps([kind, argv]))
        return 0
    if kind in ("scene", "bad"):
        return {"scene": scene, "bad": bad}[kind](argv)
    checks["file"] = path
    skip = [v for k, v in read_header(path) if k == "skip-exit"]
    checks["skip-exit"] = skip[0] if skip else None
    return run_checked(kind, argv, checks, outdir)


if __name__ == "__main__":
    mode = sys.argv[1]
    sys.exit({"scene": scene, "bad": bad, "file": test_file}[mode](sys.argv[2:]))
