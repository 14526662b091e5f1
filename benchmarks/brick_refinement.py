#!/usr/bin/env python3
"""The numerical experiment of R. Kučera, J. Haslinger, Z. Dostál, "The FETI based domain
decomposition method for solving 3D-multibody contact problems with Coulomb friction" (LNCSE 40,
Springer, 2005; doc/formulation.md, "The brick benchmark"): the brick with Coulomb friction on uniform
meshes h = 1/k, three unit cubes (12 rigid modes), F = 0.1 and 0.3, in the paper's columns
n, m, Time, Iter, n_A = n_A^QPP + n_A^QPQ, beside the paper's own numbers; Table 3 puts the time
of the quadratic-constraint solvers beside the polygonal baselines s = 2 and s = 4.

    python3 benchmarks/brick_refinement.py [--exe build/feticontact] [--k 4,6,8,10,12,16,20,24]
        [--repeats 3] [--limit "algorithm 2=12"] [--timeout 1800] [--csv doc/reports/data/brick_refinement.csv]
        [--markdown doc/reports/data/brick_refinement.md] [--only "algorithm 2,mpgp"] [--merge] [--report-only]
    /usr/bin/python3 benchmarks/brick_refinement.py --plot doc/reports/data/brick_refinement.csv doc/brick_refinement.png

Every run is `feticontact prm/kucera_table_2.prm` with the mesh, friction coefficient and
algorithm overridden (`--set`), default tolerances (QP 1e-8, MSA 1e-6, relative), no VTU output.
Time is the wall time of the contact solve (summary.json times.solve: the iterations, without
assembly and factorization, which are listed separately), the median of --repeats runs.
--limit "ALGORITHM=K;..." skips that algorithm above k = K (it does not scale; the skipped cells
say so); "ALGORITHM F0.3=K" does so for one friction coefficient only. --only measures only
the listed algorithms; --merge keeps the rows of the existing CSV that are not measured again (to add cases to an earlier study); --merge --report-only rewrites
the tables from the CSV. The measurement part uses the standard library only; --plot needs matplotlib.
"""
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

from cli import arguments, option

# The paper's Tables 1-3 (Matlab 7, Pentium 4 3 GHz), as printed. Table 2's n_A^QPP + n_A^QPQ do
# not add up to the printed n_A in the extracted text; both are quoted as printed.
PAPER = {
    "n": [900, 2646, 5832, 10890, 18252],
    "m": [180, 378, 648, 990, 1404],
    0.1: {"time": [1, 11, 34, 67, 221], "iter": [5] * 5,
          "n_A": ["102 (63+39)", "180 (98+82)", "156 (94+62)", "112 (50+62)", "155 (73+82)"]},
    0.3: {"time": [2, 12, 38, 94, 254], "iter": [7] * 5,
          "n_A": ["140 (46+32)", "186 (54+69)", "169 (72+50)", "153 (35+49)", "176 (78+54)"]},
    "time2": [15, 101, 486, 1542, 5004],
    "time4": [61, 548, 2114, 7724, 20534],
}
PAPER_K = [4, 6, 8, 10, 12]


def run_case(exe, k, friction, algorithm, polygon, repeats, timeout):
    """Runs one case `repeats` times; returns the summary of the first run with the median times."""
    settings = ["--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
                "--set", f"Contact/Zone 1/Friction coefficient={friction}",
                "--set", f"Contact solver/Algorithm={algorithm}",
                "--set", "Output/Write vtu=false"]
    if polygon:
        settings += ["--set", f"Contact solver/Expert/Polygon directions={polygon}"]
    summaries = []
    with tempfile.TemporaryDirectory() as tmp:
        for repeat in range(repeats):
            out = os.path.join(tmp, f"run{repeat}")
            try:
                # One BLAS thread: the timed work is one process per core; OpenBLAS threads
                # that spin beside other processes distort the times by up to 20x.
                env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
                subprocess.run([exe, *settings, "--set", f"Output/Directory={out}",
                                "prm/kucera_table_2.prm"], check=False, capture_output=True,
                               timeout=timeout, env=env)
            except subprocess.TimeoutExpired:
                return None
            with open(os.path.join(out, "summary.json")) as f:
                summaries.append(json.load(f))
    s = summaries[0]
    s["time_solve"] = statistics.median(x["times"]["solve"] for x in summaries)
    s["time_setup"] = statistics.median(x["times"]["total"] - x["times"]["solve"]
                                        - x["times"]["output"] for x in summaries)
    return s


def measure():
    arguments(__doc__, ["--csv", "--exe", "--k", "--limit", "--markdown", "--only",
              "--repeats", "--timeout"], ["--merge", "--report-only"])
    exe = option("--exe", "build/feticontact")
    ks = [int(v) for v in option("--k", "4,6,8,10,12,16,20,24").split(",")]
    repeats = int(option("--repeats", "3"))
    timeout = float(option("--timeout", "1800"))
    limits = {}
    for item in option("--limit", "").split(";"):
        if "=" in item:
            name, value = item.split("=")
            limits[name.strip()] = int(value)
    csv_path = option("--csv", "doc/reports/data/brick_refinement.csv")
    md_path = option("--markdown", "doc/reports/data/brick_refinement.md")

    cases = []  # (friction, algorithm label, algorithm, polygon)
    for friction in (0.1, 0.3):
        for algorithm in ("algorithm 2", "algorithm 1", "mpgp"):
            cases.append((friction, algorithm, algorithm, None))
    for s in (2, 4):
        cases.append((0.3, f"polygonal s = {s}", "polygonal", s))

    only = [v.strip() for v in option("--only", "").split(",") if v.strip()]
    rows = []
    if "--merge" in sys.argv and os.path.exists(csv_path):
        # Keep the rows of an earlier run that this run does not measure again.
        with open(csv_path) as f:
            for r in csv.DictReader(f):
                r = {key: value for key, value in r.items() if value != ""}
                r["k"], r["F"] = int(r["k"]), float(r["F"])
                for key in ("n", "m", "iter", "smalbe", "n_A", "n_A_bound", "n_A_disc"):
                    if key in r:
                        r[key] = int(r[key])
                for key in ("time_solve", "time_setup"):
                    if key in r:
                        r[key] = float(r[key])
                if not (r["k"] in ks and (not only or r["algorithm"] in only)):
                    rows.append(r)
        ks = sorted(set(ks) | {r["k"] for r in rows})
    if "--report-only" in sys.argv:
        cases = []  # only rewrite the tables from the CSV (with --merge)
    for k in ks:
        for friction, label, algorithm, polygon in cases:
            if only and label not in only:
                continue
            if any(r["k"] == k and r["F"] == friction and r["algorithm"] == label for r in rows):
                continue
            if k > limits.get(f"{label} F{friction}", limits.get(label, 10 ** 9)):
                rows.append(dict(k=k, F=friction, algorithm=label, status="skipped"))
                continue
            s = run_case(exe, k, friction, algorithm, polygon, repeats, timeout)
            if s is None:
                rows.append(dict(k=k, F=friction, algorithm=label, status="timeout"))
                print(f"k = {k}, F = {friction}, {label}: timeout", flush=True)
                continue
            h = s["hessian_multiplications"]
            c = s["contact"]
            row = dict(k=k, F=friction, algorithm=label,
                       status="converged" if s["converged"] else "not converged",
                       n=s["n_primal"], m=s["m_contact"], time_solve=round(s["time_solve"], 3),
                       time_setup=round(s["time_setup"], 3), iter=s["outer_iterations"],
                       smalbe=s["smalbe_iterations"], n_A=h["total"], n_A_bound=h["bound"],
                       n_A_disc=h["disc"], open=c["open"], stick=c["stick"], slip=c["slip"],
                       penetration=s["kkt"]["penetration"], cone=s["kkt"]["cone_violation"])
            rows.append(row)
            print(", ".join(f"{key} = {value}" for key, value in row.items()), flush=True)
            write(rows, ks, repeats, csv_path, md_path)  # after every run: partial results survive
    write(rows, ks, repeats, csv_path, md_path)
    print(f"wrote {csv_path} and {md_path}")


def write(rows, ks, repeats, csv_path, md_path):
    os.makedirs(os.path.dirname(csv_path), exist_ok=True)
    fields = ["k", "F", "algorithm", "status", "n", "m", "time_solve", "time_setup", "iter",
              "smalbe", "n_A", "n_A_bound", "n_A_disc", "open", "stick", "slip", "penetration",
              "cone"]
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow(row)
    with open(md_path, "w") as f:
        f.write(markdown(rows, ks, repeats))


def cell(rows, k, friction, label, what):
    for r in rows:
        if r["k"] == k and r["F"] == friction and r["algorithm"] == label:
            if r["status"] in ("skipped", "timeout"):
                return r["status"]
            mark = "" if r["status"] == "converged" else " (not converged)"
            if what == "time":
                return f"{r['time_solve']:.2f}{mark}"
            if what == "iter":
                return f"{r['iter']}"
            if what == "n_A":
                return f"{r['n_A']} ({r['n_A_bound']}+{r['n_A_disc']}){mark}"
    return "–"


def markdown(rows, ks, repeats):
    def first(key, k):
        for r in rows:
            if r["k"] == k and key in r:
                return r[key]
        return "–"

    out = [f"<!-- written by benchmarks/brick_refinement.py; times: median of {repeats} runs -->", ""]
    for table, friction in ((1, 0.1), (2, 0.3)):
        out.append(f"### Table {table}: F = {friction}")
        out.append("")
        out.append("| k | n | m | paper Time | paper Iter | paper n_A | Alg. 2 Time | Alg. 2 Iter | Alg. 2 n_A "
                   "| Alg. 1 Time | Alg. 1 Iter | Alg. 1 n_A | MPGP Time | MPGP Iter | MPGP n_A |")
        out.append("|---" * 15 + "|")
        for k in ks:
            i = PAPER_K.index(k) if k in PAPER_K else None
            paper = [str(PAPER[friction]["time"][i]), str(PAPER[friction]["iter"][i]),
                    PAPER[friction]["n_A"][i]] if i is not None else ["", "", ""]
            cells = []
            for label in ("algorithm 2", "algorithm 1", "mpgp"):
                cells += [cell(rows, k, friction, label, w) for w in ("time", "iter", "n_A")]
            out.append(f"| {k} | {first('n', k)} | {first('m', k)} | " + " | ".join(paper + cells) + " |")
        out.append("")
    out.append("### Table 3: F = 0.3, time (s) of the quadratic-constraint solvers and the polygonal baselines")
    out.append("")
    out.append("| k | n | m | paper Time | paper Time2 | paper Time4 | Alg. 2 | MPGP | s = 2 | s = 4 "
               "| s = 2 / MPGP | s = 4 / MPGP | n_A s = 2 | n_A s = 4 |")
    out.append("|---" * 14 + "|")
    for k in ks:
        i = PAPER_K.index(k) if k in PAPER_K else None
        paper = [str(PAPER[0.3]["time"][i]), str(PAPER["time2"][i]), str(PAPER["time4"][i])] \
            if i is not None else ["", "", ""]
        t = {label: cell(rows, k, 0.3, label, "time")
             for label in ("algorithm 2", "mpgp", "polygonal s = 2", "polygonal s = 4")}

        def ratio(a, b):
            try:
                return f"{float(t[a].split()[0]) / float(t[b].split()[0]):.1f}"
            except ValueError:
                return "–"
        out.append(f"| {k} | {first('n', k)} | {first('m', k)} | " + " | ".join(
            paper + [t["algorithm 2"], t["mpgp"], t["polygonal s = 2"], t["polygonal s = 4"],
                    ratio("polygonal s = 2", "mpgp"), ratio("polygonal s = 4", "mpgp"),
                    cell(rows, k, 0.3, "polygonal s = 2", "n_A"),
                    cell(rows, k, 0.3, "polygonal s = 4", "n_A")]) + " |")
    out.append("")
    return "\n".join(out)


def plot(csv_path, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(csv_path) as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "converged"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    styles = {"algorithm 2": "o-", "algorithm 1": "s-", "mpgp": "^-", "polygonal s = 2": "v--",
              "polygonal s = 4": "d--"}
    for friction, colour in (("0.1", "tab:blue"), ("0.3", "tab:red")):
        for label, style in styles.items():
            sel = sorted((int(r["n"]), r) for r in rows if r["F"] == friction and r["algorithm"] == label)
            if not sel:
                continue
            n = [x for x, _ in sel]
            kw = dict(color=colour if not label.startswith("polygonal") else "tab:gray")
            axes[0].loglog(n, [int(r["n_A"]) for _, r in sel], style, label=f"{label}, F = {friction}", **kw)
            axes[1].loglog(n, [float(r["time_solve"]) for _, r in sel], style,
                           label=f"{label}, F = {friction}", **kw)
    for friction, colour in ((0.1, "tab:blue"), (0.3, "tab:red")):
        paper_nA = [int(v.split()[0]) for v in PAPER[friction]["n_A"]]
        axes[0].loglog(PAPER["n"], paper_nA, "x:", color=colour, label=f"paper, μ = {friction}")
        axes[1].loglog(PAPER["n"], PAPER[friction]["time"], "x:", color=colour,
                       label=f"paper (Matlab, Pentium 4), μ = {friction}")
    axes[0].set_xlabel("n (primal unknowns)")
    axes[0].set_ylabel("n_A (multiplications by the Hessian)")
    axes[1].set_xlabel("n (primal unknowns)")
    axes[1].set_ylabel("time of the contact solve (s)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, loc="upper left")
    fig.suptitle("Brick with Coulomb friction, three subdomains, h = 1/k")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        plot(sys.argv[i + 1], sys.argv[i + 2])
    else:
        measure()
