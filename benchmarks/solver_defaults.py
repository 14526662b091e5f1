#!/usr/bin/env python3
"""Which solver options are defaults: every option of the contact solver measured, one at a
time, against the default configuration, on the brick (F = 0.1 and 0.3; k = 8, 16, 24),
two_blocks, hertz and cattaneo_mindlin.

    /usr/bin/python3 benchmarks/solver_defaults.py [--exe build/feticontact] [--prm prm]
        [--cases brick_F0.3_k8,...] [--variants defaults,...] [--repeats 1] [--time-limit 300]
        [--csv doc/reports/data/solver_defaults.csv] [--markdown doc/reports/data/solver_defaults.md]
        [--report-only]

Every case is run with the defaults (`variant` "defaults": nothing set in `subsection Contact
solver` except what the scene itself sets, whose lines the case removes: the scenes of the
paper's tables, prm/kucera_table_*.prm, choose Algorithm 2) and with each variant, which sets one entry of `Contact solver`
(its Expert, MPGP or SMALBE subsection) to another value. A variant that needs more multiplications than the defaults in every
case, or fails where the defaults converge, is worse; one that needs fewer in some case is
listed with the ratio; a run that takes longer than --time-limit seconds is stopped and counted
as not converged. The counts (n_A, Hessian multiplications; outer iterations) do not
depend on the machine; times are the solve phase of summary.json, medians of --repeats runs.
The brick's decomposition is the automatic one. The CSV is rewritten after every run;
--report-only rewrites the table from it. Standard library only.
"""
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from rows import write_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

EXPERT = "Contact solver/Expert/"
MPGP = "Contact solver/MPGP/"
SMALBE = "Contact solver/SMALBE/"
# The variants: one entry changed from its default. The defaults' own values are in
# `feticontact --print-parameters`.
VARIANTS = {
    "defaults": [],
    "expansion fixed": [MPGP + "Expansion step=fixed"],
    "hessian norm sum": [SMALBE + "Hessian norm bound=sum"],
    "inexact MSA 0.01": [EXPERT + "Inexact MSA factor=0.01"],
    "recursive gradient 0": [MPGP + "Recursive gradient tolerance=0"],
    "arc scale norm": [MPGP + "Arc preconditioner scale=norm"],
    "penalty factor 3": [SMALBE + "Penalty factor=3"],
    "penalty factor 10": [SMALBE + "Penalty factor=10"],
    "multiplier step 1.5": [SMALBE + "Multiplier step factor=1.5"],
    "inner floor 0.1": [SMALBE + "Inner tolerance floor=0.1"],
}


def brick(friction, k):
    sets = [f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}"]
    if friction != 0.3:
        sets.append(f"Contact/Zone 1/Friction coefficient={friction}")
    return ("brick_contact.prm", sets)


CASES = {
    **{f"brick_F{F}_k{k}": brick(F, k) for F in (0.1, 0.3) for k in (8, 16, 24)},
    "two_blocks": ("two_blocks.prm", []),
    "hertz": ("hertz.prm", []),
    "cattaneo_mindlin": ("cattaneo_mindlin.prm", []),
}

FIELDS = ["case", "variant", "run", "converged", "n_A", "outer_iterations", "F_applications",
          "solve_s", "total_s", "n_subdomains", "n_primal"]


def scene_without_solver_choices(prm_dir, name, directory):
    """The scene's parameter file without its `Contact solver` and `FETI` subsections (they
    choose the paper's algorithm or a decomposition for the paper's tables) and without its
    `Decomposition` subsections: the defaults decide."""
    out = []
    skip = 0
    with open(os.path.join(prm_dir, name), encoding="utf-8") as f:
        for line in f:
            words = line.split()
            if skip:
                if words[:1] == ["subsection"]:
                    skip += 1
                elif words[:1] == ["end"]:
                    skip -= 1
                continue
            if words[:1] == ["subsection"] and " ".join(words[1:]) in (
                    "Contact solver", "FETI", "Decomposition"):
                skip = 1
                continue
            if "Mesh file" in line or "Reference" in line:
                # Relative file names stay relative to the scene's folder.
                key, _, value = line.partition("=")
                if value.strip() and not os.path.isabs(value.strip()):
                    line = f"{key}= {os.path.join(prm_dir, value.strip())}\n"
            out.append(line)
    path = os.path.join(directory, name)
    with open(path, "w", encoding="utf-8") as f:
        f.writelines(out)
    return path


def run(exe, prm_dir, case, variant, directory, time_limit):
    prm, sets = CASES[case]
    path = scene_without_solver_choices(prm_dir, prm, directory)
    output = os.path.join(directory, "out")
    command = [exe, "--set", f"Output/Directory={output}", "--set", "Output/Write vtu=false"]
    for s in sets + VARIANTS[variant]:
        command += ["--set", s]
    command.append(path)
    try:
        result = subprocess.run(command, capture_output=True, text=True, timeout=time_limit)
    except subprocess.TimeoutExpired:
        shutil.rmtree(output, ignore_errors=True)
        return {"case": case, "variant": variant, "converged": f"no: over {time_limit} s",
                "n_A": "", "outer_iterations": "", "F_applications": "", "solve_s": "",
                "total_s": "", "n_subdomains": "", "n_primal": ""}
    summary_path = os.path.join(output, "summary.json")
    if not os.path.exists(summary_path):
        raise SystemExit(f"{case} / {variant}: exit {result.returncode}\n{result.stderr[-2000:]}")
    with open(summary_path, encoding="utf-8") as f:
        s = json.load(f)
    row = {"case": case, "variant": variant, "converged": s["converged"],
           "n_A": s["hessian_multiplications"]["total"],
           "outer_iterations": s.get("outer_iterations", ""),
           "F_applications": s["hessian_multiplications"].get("F_applications", ""),
           "solve_s": s["times"]["solve"],
           "total_s": s["times"]["total"] - s["times"]["output"],
           "n_subdomains": s["n_subdomains"], "n_primal": s["n_primal"]}
    shutil.rmtree(output)
    return row


def report(rows, markdown):
    cases = list(dict.fromkeys(r["case"] for r in rows))
    variants = list(dict.fromkeys(r["variant"] for r in rows))

    def median(case, variant, key):
        values = [float(r[key]) for r in rows
                  if r["case"] == case and r["variant"] == variant and r[key] != ""]
        return statistics.median(values) if values else None

    def converged(case, variant):
        return all(r["converged"] in (True, "True") for r in rows
                   if r["case"] == case and r["variant"] == variant)

    lines = ["| case | n | subdomains | defaults: n_A, solve s | "
             + " | ".join(v for v in variants if v != "defaults") + " |",
             "|---|---|---|---|" + "---|" * (len(variants) - 1)]
    for case in cases:
        base = median(case, "defaults", "n_A")
        base_t = median(case, "defaults", "solve_s")
        first = next(r for r in rows if r["case"] == case)
        cells = [case, first["n_primal"], first["n_subdomains"],
                 f"{base:.0f}, {base_t:.2f}" if base is not None else "—"]
        for v in variants:
            if v == "defaults":
                continue
            n = median(case, v, "n_A")
            t = median(case, v, "solve_s")
            if n is None:
                cells.append("not converged" if not converged(case, v) else "—")
            elif not converged(case, v):
                cells.append(f"{n:.0f} (not converged)")
            elif t is None:
                cells.append("—")
            else:
                cells.append(f"{n:.0f} ({n / base:.2f}), {t / base_t:.2f}" if base else f"{n:.0f}")
        lines.append("| " + " | ".join(str(c) for c in cells) + " |")
    text = ("Hessian multiplications n_A of each variant, in parentheses relative to the "
            "defaults, then its solve time relative to the defaults' (`solve` of summary.json, "
            "median of the runs).\n\n" + "\n".join(lines) + "\n")
    with open(markdown, "w", encoding="utf-8") as f:
        f.write(text)
    print(text)


def main():
    arguments(__doc__, ["--exe", "--prm", "--cases", "--variants", "--repeats", "--time-limit", "--csv",
                        "--markdown"], ["--report-only"])
    exe = os.path.abspath(option("--exe", os.path.join(ROOT, "build", "feticontact")))
    prm_dir = os.path.abspath(option("--prm", os.path.join(ROOT, "prm")))
    cases = option("--cases", ",".join(CASES)).split(",")
    variants = option("--variants", ",".join(VARIANTS)).split(",")
    repeats = int(option("--repeats", "1"))
    time_limit = float(option("--time-limit", "300"))
    csv_path = option("--csv", os.path.join(ROOT, "doc", "reports", "data", "solver_defaults.csv"))
    markdown = option("--markdown", os.path.join(ROOT, "doc", "reports", "data", "solver_defaults.md"))
    for name in cases:
        if name not in CASES:
            raise SystemExit(f"unknown case '{name}'; known: {', '.join(CASES)}")
    for name in variants:
        if name not in VARIANTS:
            raise SystemExit(f"unknown variant '{name}'; known: {', '.join(VARIANTS)}")
    rows = []
    if os.path.exists(csv_path):
        with open(csv_path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    if "--report-only" not in sys.argv:
        rows = [r for r in rows if not (r["case"] in cases and r["variant"] in variants)]
        with tempfile.TemporaryDirectory() as directory:
            for case in cases:
                for variant in variants:
                    for repeat in range(repeats):
                        row = run(exe, prm_dir, case, variant, directory, time_limit)
                        row["run"] = repeat + 1
                        rows.append(row)
                        print(f"{case:22s} {variant:24s} n_A {row['n_A']} "
                              f"solve {row['solve_s']} s  converged {row['converged']}",
                              flush=True)
                        write_rows(csv_path, FIELDS, rows)
    report(rows, markdown)


if __name__ == "__main__":
    main()
