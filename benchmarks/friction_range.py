#!/usr/bin/env python3
"""The solver across the range of the friction coefficient on the paper's brick (doc/formulation.md, "The brick benchmark"),
and the effect of the two parameters meant for large F: relaxation of the slip-bound update
(`Contact solver/Expert/Relaxation` ω) and continuation in F (`Contact solver/Friction continuation
steps` n).

    python3 benchmarks/friction_range.py [--exe build/feticontact] [--k 4,8] [--repeats 3]
        [--single-above 60] [--markdown doc/reports/data/friction_range.md]

Part 1: F = 0, 1e-8, 0.1, 0.3, 0.5, 1, 2 with every algorithm (default tolerances): status,
Iter, n_A, time of the solve (median of --repeats runs), open/stick/slip counts.
Part 2: F = 0.5, 1, 2 with ω ∈ {1, 0.5} and n ∈ {1, 4}.
A setting whose first run takes longer than --single-above seconds is run once (the table marks
it): n_A, the measure of cost here, does not vary between runs. The table is rewritten after
every row, so an interrupted run leaves the rows it measured.
Standard library only.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

from cli import arguments, option

PRM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "prm", "kucera_table_2.prm")
ALGORITHMS = ["algorithm 2", "algorithm 1", "mpgp"]


def run(exe, k, friction, algorithm, repeats, single_above, extra=()):
    settings = ["--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
                "--set", f"Contact/Zone 1/Friction coefficient={friction}",
                "--set", f"Contact solver/Algorithm={algorithm}",
                "--set", "Output/Write vtu=false", "--set", "Output/Write displacement csv=false"]
    for e in extra:
        settings += ["--set", e]
    times, summary, code = [], None, 0
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as out:
            p = subprocess.run([exe, *settings, "--set", f"Output/Directory={out}", PRM],
                               capture_output=True, text=True, timeout=3600, env=env)
            code = p.returncode
            path = os.path.join(out, "summary.json")
            if not os.path.exists(path):
                return {"status": f"exit {code}, no summary"}
            with open(path) as f:
                summary = json.load(f)
        times.append(summary["times"]["solve"])
        if not summary["converged"] or summary["times"]["solve"] > single_above:
            break
    c = summary.get("contact", {})
    return {"status": "converged" if summary["converged"] else
            f"exit {code}: {summary.get('solver_message', '')}",
            "iter": summary["outer_iterations"], "n_A": summary["hessian_multiplications"]["total"],
            "time": f"{statistics.median(times):.3g}" + ("" if len(times) == repeats else " (1 run)"),
            "open": c.get("open"), "stick": c.get("stick"),
            "slip": c.get("slip"), "cone": summary.get("kkt", {}).get("cone_violation")}


def write(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    arguments(__doc__, ["--exe", "--k", "--markdown", "--repeats", "--single-above"], [])
    exe = option("--exe", "build/feticontact")
    ks = [int(v) for v in option("--k", "4,8").split(",")]
    repeats = int(option("--repeats", "3"))
    single_above = float(option("--single-above", "60"))
    md_path = option("--markdown", "doc/reports/data/friction_range.md")
    out = ["<!-- written by benchmarks/friction_range.py -->", "",
           f"Command: `python3 {' '.join(sys.argv)}`; time: the contact solve, median of "
           f"{repeats} runs (one for a run that does not converge or takes more than "
           f"{single_above:g} s).", "",
           "### The range of F (default tolerances: MSA 1e-6, QP 1e-8)", "",
           "| k | F | algorithm | status | Iter | n_A | solve [s] | open/stick/slip |",
           "|---|---|---|---|---|---|---|---|"]
    for k in ks:
        for friction in ["0", "1e-8", "0.1", "0.3", "0.5", "1", "2"]:
            for algorithm in ALGORITHMS:
                r = run(exe, k, friction, algorithm, repeats, single_above)
                line = (f"| {k} | {friction} | {algorithm} | {r['status']} | {r.get('iter', '')} | "
                        f"{r.get('n_A', '')} | {r.get('time', '')} | "
                        f"{r.get('open')}/{r.get('stick')}/{r.get('slip')} |")
                print(line, flush=True)
                out.append(line)
                write(md_path, out)
    out += ["", "### Relaxation ω and continuation in F (n stages) at F ≥ 0.5", "",
            "| k | F | algorithm | ω | n | status | Iter | n_A | solve [s] |",
            "|---|---|---|---|---|---|---|---|---|"]
    for k in ks:
        for friction in ["0.5", "1", "2"]:
            for algorithm in ALGORITHMS:
                for omega in ["1", "0.5"]:
                    for stages in ["1", "4"]:
                        r = run(exe, k, friction, algorithm, repeats, single_above,
                                [f"Contact solver/Expert/Relaxation={omega}",
                                 f"Contact solver/Expert/Friction continuation steps={stages}"])
                        line = (f"| {k} | {friction} | {algorithm} | {omega} | {stages} | "
                                f"{r['status']} | {r.get('iter', '')} | {r.get('n_A', '')} | "
                                f"{r.get('time', '')} |")
                        print(line, flush=True)
                        out.append(line)
                        write(md_path, out)
    print("wrote", md_path)


if __name__ == "__main__":
    main()
