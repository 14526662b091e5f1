#!/usr/bin/env python3
"""Performance at scale on the brick (doc/formulation.md, "The brick benchmark"; friction
coefficient μ = 0.3, MPGP, TFETI, default tolerances):
numerical scalability with the subdomain size fixed, MPI speed-up on this machine, the cost
floor, peak memory, the coarse problem against the number of subdomains, and one monolithic
linear solve beside the contact solve.

    python3 benchmarks/scaling.py [--exe build/feticontact]
        [--monolithic build/benchmarks/monolithic_solve] [--cells-per-subdomain 8]
        [--a 1,2,3,4,5,6] [--np 1,2] [--paper-k 8,16] [--coarse-a 1,3,5,7] [--repeats 1]
        [--csv doc/reports/data/scaling.csv] [--linear-csv doc/reports/data/scaling_linear.csv]
        [--markdown doc/reports/data/scaling.md] [--merge] [--report-only] [--linear-only]
        [--expansion "projected cg"] [--hessian-norm-bound max]
        [--inexact-msa-factor 0.001] [--recursive-gradient-tolerance 0.1]
        [--arc-scale "mean diagonal"] [--penalty-factor 3] [--multiplier-step 1.5]
        [--add-summary SERIES,A,C,NP,PATH/summary.json]
        [--pair-a 2,3] [--alternate]
    /usr/bin/python3 benchmarks/scaling.py --plot doc/reports/data/scaling.csv doc/scaling.png

Weak scaling ("fixed H/h"): the brick (0,3)×(0,1)×(0,1) with h = 1/k, k = a × c (c =
--cells-per-subdomain), split into 3a × a × a cubic subdomains of c × c × c cells, for every a
of --a; each is run with every rank count of --np (`mpirun -np P`, one OpenBLAS thread per
rank; the --repeats runs of one rank count, then those of the next; with --alternate the runs
alternate, 1, 2, 1, 2, …, which spreads a drift of the machine's speed over all rank counts
but, on the machine of doc/performance.md, slows every one-rank run that follows a two-rank
run by 10–20 %). "Paper's setting": three subdomains (blocks 3, 1, 1) at the k of --paper-k, so
that H/h = k grows (the decomposition of R. Kučera, J. Haslinger, Z. Dostál, LNCSE 40, 2005). "Coarse problem": c = 2 and a of --coarse-a (3a³ subdomains, up to 1,029 at a = 7),
where the time of setting up the coarse problem GGᵀ is read. --monolithic gives the program that
assembles the stiffness of the undecomposed brick and solves the linear elastic problem with
CHOLMOD (benchmarks/monolithic_solve.cc); it is run once per a, and its rows go to --linear-csv
(--linear-only runs only these, e.g. on the second core beside a one-rank study).
--expansion sets MPGP's `Contact solver/MPGP/Expansion step` (default fixed; the program's default
for mpgp is projected cg); other than fixed, the series are named "weak_pcg" etc. --hessian-norm-bound sets `Contact solver/SMALBE/Hessian norm bound`
(default sum; max: the series get the suffix "_max", e.g. "weak_max", "weak_pcg_max").
--inexact-msa-factor and --recursive-gradient-tolerance set `Contact solver/Expert/Inexact MSA factor`
and `Contact solver/MPGP/Recursive gradient tolerance` (suffixes "_c0.001", "_r0.1"; unset: the
program's default); every series has its own tables, and its own MPI tables; --arc-scale sets
`Contact solver/MPGP/Arc preconditioner scale` (default norm; "mean diagonal": suffix "_md") and
--penalty-factor `Contact solver/SMALBE/Penalty factor` (unset: the program's default, 5 for mpgp;
suffix "_f3" for 3), --multiplier-step `Contact solver/SMALBE/Multiplier step factor`
(default 1; suffix "_s1.5" for 1.5) when it was run on more than one rank count. --add-summary adds the row of a run made with the same settings
whose summary.json was kept (e.g. a long run whose study was interrupted) and rewrites the tables.
--pair-a measures what two cores of this machine allow, for the fixed-H/h cases of the given a:
the one-rank run alone, then two copies of it at the same time on the two cores (taskset), in
turn --repeats times. Two independent copies need no communication and do the same work, so
2 × (time alone) / (time of a copy in the pair) bounds the speed-up of two ranks from above; with
memory-bandwidth-bound local solves it is below 2.

Times come from summary.json (TimerOutput phases) and are medians of --repeats runs; "total" is
the run without output (setup, assembly, factorization, coarse problem, solve, primal recovery),
the quantity that summary.json's total_over_floor compares with the cost floor; peak memory
is the largest peak resident set size of the ranks. The CSV is rewritten after every run, so an
interrupted study keeps what it measured; --merge keeps the rows of the existing CSV that are not
measured again, also those that another study writes into the same CSV meanwhile (two studies
may run side by side); --report-only rewrites the tables from the CSV. Standard library only, except
--plot (matplotlib).
"""
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

from cli import arguments, option

PRM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "prm", "brick_contact.prm")
FIELDS = ["series", "a", "c", "k", "np", "n_subdomains", "n", "m", "coarse", "iter", "smalbe",
          "n_A", "setup", "assembly", "factorization", "coarse_problem", "solve", "hessian",
          "bookkeeping", "one_F", "total", "floor_ratio", "peak_mib", "converged", "runs",
          "local_slowest", "local_fastest"]
MONO_FIELDS = ["series", "a", "c", "k", "n", "assembly", "factorization", "solve", "linear_total",
               "peak_mib", "residual", "factor_entries"]


DEFAULT_VARIANT = ("fixed", "sum", "", "", "norm", "F", "", "")


def settings(k, blocks, variant=DEFAULT_VARIANT):
    expansion, bound, msa_factor, recursive, arc_scale, penalty_norm, factor, step = variant
    return ["--set", f"Contact solver/MPGP/Expansion step={expansion}",
            "--set", f"Contact solver/SMALBE/Hessian norm bound={bound}",
            *(["--set", f"Contact solver/Expert/Inexact MSA factor={msa_factor}"] if msa_factor else []),
            *(["--set", f"Contact solver/MPGP/Recursive gradient tolerance={recursive}"]
              if recursive else []),
            "--set", f"Contact solver/MPGP/Arc preconditioner scale={arc_scale}",
            *(["--set", f"Contact solver/SMALBE/Penalty factor={factor}"] if factor else []),
            *(["--set", f"Contact solver/SMALBE/Multiplier step factor={step}"] if step else []),
            "--set", f"Body 1/Mesh/Subdivisions={3 * k}, {k}, {k}",
            "--set", "Body 1/Decomposition/Method=blocks",
            "--set", f"Body 1/Decomposition/Blocks={blocks[0]}, {blocks[1]}, {blocks[2]}",
            "--set", "Contact/Zone 1/Friction coefficient=0.3",
            "--set", "Contact solver/Algorithm=mpgp",
            "--set", "FETI/Dirichlet treatment=total",
            "--set", "Output/Write vtu=false",
            "--set", "Output/Write displacement csv=false"]


def env():
    return dict(os.environ, OPENBLAS_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def contact_command(exe, k, blocks, out, variant=DEFAULT_VARIANT):
    return [exe, *settings(k, blocks, variant), "--set", f"Output/Directory={out}", PRM]


def read_summary(p, command, out):
    path = os.path.join(out, "summary.json")
    if p.returncode != 0 or not os.path.exists(path):
        raise SystemExit(f"run failed (exit {p.returncode}): {' '.join(command)}\n"
                         f"{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    with open(path) as f:
        return json.load(f)


def run_contact_once(exe, k, blocks, ranks, variant=DEFAULT_VARIANT):
    """summary.json of one run on `ranks` ranks."""
    with tempfile.TemporaryDirectory() as out:
        command = contact_command(exe, k, blocks, out, variant)
        if ranks > 1:
            command = ["mpirun", "-np", str(ranks), "--bind-to", "core"] + command
        p = subprocess.run(command, capture_output=True, text=True, env=env())
        return read_summary(p, command, out)


def run_contact(exe, series, a, c, k, blocks, ranks, repeats, variant=DEFAULT_VARIANT):
    runs = [run_contact_once(exe, k, blocks, ranks, variant) for _ in range(repeats)]
    return row_from_summaries(runs, series, a, c, k, ranks)


def run_contact_interleaved(exe, series, a, c, k, blocks, rank_counts, repeats, variant):
    """The runs of every rank count in turn (1, 2, 1, 2, …; --alternate), so that a drift of the
    machine's speed over the study falls on all rank counts alike. On the machine of
    doc/performance.md a one-rank run right after a two-rank run is 10–20 % slower, so there
    this order overstates the speed-up. One row per rank count."""
    runs = {p: [] for p in rank_counts}
    for _ in range(repeats):
        for p in rank_counts:
            runs[p].append(run_contact_once(exe, k, blocks, p, variant))
    return [row_from_summaries(runs[p], series, a, c, k, p) for p in rank_counts]


def run_pair(exe, a, c, k, blocks, repeats, variant=DEFAULT_VARIANT, suffix=""):
    """What the hardware allows two ranks: the one-rank run alone on core 0, then two copies
    of it at once on cores 0 and 1 (taskset), `repeats` times in turn. The rows "pair_alone"
    (np 1) and "pair" (np 2: the median over both copies) of the same cases, with the series
    suffix of the solver settings (`variant`)."""
    alone, pair = [], []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as out:
            command = ["taskset", "-c", "0"] + contact_command(exe, k, blocks, out, variant)
            p = subprocess.run(command, capture_output=True, text=True, env=env())
            alone.append(read_summary(p, command, out))
        with tempfile.TemporaryDirectory() as out0, tempfile.TemporaryDirectory() as out1:
            commands = [["taskset", "-c", str(core)] + contact_command(exe, k, blocks, out, variant)
                        for core, out in [(0, out0), (1, out1)]]
            procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                      text=True, env=env()) for cmd in commands]
            for cmd, proc, out in zip(commands, procs, [out0, out1]):
                stdout, stderr = proc.communicate()
                pair.append(read_summary(subprocess.CompletedProcess(cmd, proc.returncode,
                                                                     stdout, stderr), cmd, out))
    return (row_from_summaries(alone, "pair_alone" + suffix, a, c, k, 1),
            row_from_summaries(pair, "pair" + suffix, a, c, k, 2))


def row_from_summaries(runs, series, a, c, k, ranks):
    """The table row of the runs (summary.json contents) of one case."""
    first = runs[0]
    for r in runs[1:]:
        if r["hessian_multiplications"]["total"] != first["hessian_multiplications"]["total"]:
            print(f"warning: n_A differs between repeats ({r['hessian_multiplications']['total']}"
                  f" vs {first['hessian_multiplications']['total']})", flush=True)

    def median(name):
        return statistics.median(r["times"][name] for r in runs)

    def median_if_present(name):
        # The work in a rank's own subdomains (absent from the summaries of old programs).
        values = [r["times"][name] for r in runs if name in r["times"]]
        return statistics.median(values) if values else ""

    return {"series": series, "a": a, "c": c, "k": k, "np": ranks,
            "n_subdomains": first["n_subdomains"], "n": first["n_primal"],
            "m": first["m_total"], "coarse": first["n_rigid_modes"],
            "iter": first["outer_iterations"], "smalbe": first["smalbe_iterations"],
            "n_A": first["hessian_multiplications"]["total"],
            "setup": median("setup"), "assembly": median("assembly"),
            "factorization": median("factorization"), "coarse_problem": median("coarse_problem"),
            "solve": median("solve"), "hessian": median("hessian_applications"),
            "bookkeeping": median("qp_bookkeeping"), "one_F": median("one_hessian_application"),
            "total": statistics.median(r["times"]["total"] - r["times"]["output"] for r in runs),
            "floor_ratio": median("total_over_floor"),
            "peak_mib": max(r["memory"]["peak_rss_mib_max"] for r in runs),
            "converged": all(r["converged"] for r in runs), "runs": len(runs),
            "local_slowest": median_if_present("hessian_local_slowest_rank"),
            "local_fastest": median_if_present("hessian_local_fastest_rank")}


def run_monolithic(exe, a, c, k):
    command = [exe, *settings(k, (1, 1, 1)), PRM]
    p = subprocess.run(command, capture_output=True, text=True, env=env())
    if p.returncode != 0:
        raise SystemExit(f"monolithic solve failed (exit {p.returncode}): {' '.join(command)}\n"
                         f"{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    result = json.loads(p.stdout.strip().splitlines()[-1])
    return {"series": "linear", "a": a, "c": c, "k": k, "n": result["n"],
            "assembly": result["assembly"], "factorization": result["factorization"],
            "solve": result["solve"],
            "linear_total": result["assembly"] + result["factorization"] + result["solve"],
            "peak_mib": result["peak_rss_mib"], "residual": result["relative_residual"],
            "factor_entries": result["factor_entries"]}


def key(row):
    return (row["series"], int(row["a"]), int(row["c"]), int(row.get("np") or 0))


def save(path, rows, fields):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in sorted(rows, key=key):
            w.writerow(r)


def load(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def g(value, digits=3):
    return f"{float(value):.{digits}g}"


def variant_suffixes(contact, base):
    """The suffixes of the series of `base` in the rows ("", "_pcg_max", "_pcg_max_c0.001", …),
    the default first."""
    found = {r["series"][len(base):] for r in contact if r["series"].startswith(base) and
             (r["series"] == base or r["series"][len(base)] == "_")}
    order = ["", "_pcg", "_max", "_pcg_max"]
    return sorted(found, key=lambda x: (order.index(x) if x in order else len(order), x))


def variant_note(suffix):
    """', Expansion step = projected cg, …' for a series suffix ("_pcg_max_c0.001_r0.1")."""
    names = {"pcg": "Expansion step = projected cg", "max": "Hessian norm bound = max",
             "c": "Inexact MSA factor = ", "r": "Recursive gradient tolerance = ",
             "md": "Arc preconditioner scale = mean diagonal",
             "f": "Penalty factor = ",
             "s": "Multiplier step factor = "}
    notes = []
    for token in suffix.split("_")[1:]:
        if token in names:
            notes.append(names[token])
        elif token[0] in "crfs":
            notes.append(names[token[0]] + token[1:])
    return "".join(", " + n for n in notes)


def mpi_tables(out, contact, series, note):
    """The tables of one series measured on one and more ranks: wall time and speed-up, and
    where the time of the multi-rank runs goes."""
    weak = [r for r in contact if r["series"] == series]
    ranks = sorted({int(r["np"]) for r in weak})
    if len(ranks) < 2:
        return
    out.extend([f"### MPI{note}: wall time without output (total) on 1 and more ranks", "",
                "'speed-up' is the ratio of the medians. On the virtual machine of these "
                "runs a one-rank run right after a two-rank run was 10–20 % slower than "
                "after a one-rank run (doc/performance.md): measure in "
                "blocks (the default; not --alternate), whose ratios do not overstate the "
                "speed-up.", "",
                "| k | n | subdomains | " + " | ".join(f"total np={p}" for p in ranks) +
                " | " + " | ".join(f"speed-up np={p} | efficiency np={p}"
                                   for p in ranks[1:]) +
                " | " + " | ".join(f"peak MiB/rank np={p}" for p in ranks) + " |",
                "|" + "---|" * (3 + len(ranks) + 2 * (len(ranks) - 1) + len(ranks))])
    for k in sorted({int(r["k"]) for r in weak}):
        by = {int(r["np"]): r for r in weak if int(r["k"]) == k}
        if 1 not in by:
            continue
        t1 = float(by[1]["total"])
        cells = [g(by[p]["total"]) if p in by else "" for p in ranks]
        for p in ranks[1:]:
            cells += ([f"{t1 / float(by[p]['total']):.2f}",
                       f"{t1 / float(by[p]['total']) / p:.2f}"] if p in by else ["", ""])
        cells += [f"{float(by[p]['peak_mib']):.0f}" if p in by else "" for p in ranks]
        out.append(f"| {k} | {by[1]['n']} | {by[1]['n_subdomains']} | " +
                   " | ".join(cells) + " |")
    out.append("")
    # Where the time of the multi-rank runs goes beside the local work.
    split = [r for r in weak if r.get("local_slowest") and int(r["np"]) > 1]
    if split:
        out.extend([f"### MPI{note}: the applications of F and the bookkeeping on more ranks", "",
                    "'F' = the applications of F on the slowest rank; 'local' = its work in "
                    "its own subdomains (the slowest and the fastest rank); 'exchange and "
                    "waiting' = F − local (slowest rank; of the medians), the exchange of B u among "
                    "the ranks and the waits for the other rank; 'bookkeeping' = the rest of the solve "
                    "(the QP work on the dual vectors and the split products with G). Medians [s].", "",
                    "| k | np | F | local, slowest rank | local, fastest rank | "
                    "exchange and waiting | bookkeeping | runs |",
                    "|---|---|---|---|---|---|---|---|"])
        for r in sorted(split, key=lambda r: (int(r["k"]), int(r["np"]))):
            out.append(f"| {r['k']} | {r['np']} | {g(r['hessian'])} | "
                       f"{g(r['local_slowest'])} | {g(r['local_fastest'])} | "
                       f"{g(float(r['hessian']) - float(r['local_slowest']))} | "
                       f"{g(r['bookkeeping'])} | {r['runs']} |")
        out.append("")


def pair_table(out, contact, suffix=""):
    """What two cores allow: one run alone against two copies at once (--pair-a), for the
    solver settings of the series suffix."""
    weak = [r for r in contact if r["series"] == "weak" + suffix]
    pairs = {int(r["k"]): r for r in contact if r["series"] == "pair" + suffix}
    if pairs:
        out.extend(["### What two cores allow: one run alone against two copies at once"
                    + variant_note(suffix), "",
                    "Two independent one-rank runs on cores 0 and 1 (`--pair-a`); 'bound' = "
                    "2 × alone / in the pair, the speed-up that two ranks cannot exceed on this "
                    "machine; 'np=2 measured' from the MPI table above.", "",
                    "| k | n | one F alone [s] | one F in the pair [s] | bound for F | "
                    "total alone [s] | total in the pair [s] | bound for the run | "
                    "np=2 measured | runs |",
                    "|---|---|---|---|---|---|---|---|---|---|"])
        for k, r in sorted(pairs.items()):
            alone = [x for x in contact
                     if x["series"] == "pair_alone" + suffix and int(x["k"]) == k]
            if not alone:
                continue
            al = alone[0]
            by = {int(x["np"]): x for x in weak if int(x["k"]) == k}
            measured = (f"{float(by[1]['total']) / float(by[2]['total']):.2f}"
                        if 1 in by and 2 in by else "")
            out.append(f"| {k} | {r['n']} | {g(al['one_F'])} | {g(r['one_F'])} | "
                       f"{2 * float(al['one_F']) / float(r['one_F']):.2f} | {g(al['total'])} | "
                       f"{g(r['total'])} | {2 * float(al['total']) / float(r['total']):.2f} | "
                       f"{measured} | {al['runs']} |")
        out.append("")


def report(rows, md_path, command):
    contact = [r for r in rows if r["series"] != "linear"]
    linear = {int(r["a"]): r for r in rows if r["series"] == "linear"}
    out = ["<!-- written by benchmarks/scaling.py -->", "",
           "Tables written by benchmarks/scaling.py from the rows of the CSV files beside this "
           "file (the commands that measured them: doc/performance.md). Brick, friction "
           "coefficient μ = 0.3, MPGP, TFETI, "
           "CHOLMOD, default tolerances "
           "(MSA 1e-6, QP 1e-8); times [s] from summary.json, medians of the runs counted in "
           "'runs'; one OpenBLAS thread per rank.", ""]

    def table(title, series, ranks):
        sel = sorted([r for r in contact if r["series"] == series and int(r["np"]) == ranks],
                     key=lambda r: int(r["k"]))
        if not sel:
            return
        n_a0 = float(sel[0]["n_A"])
        out.extend([f"### {title}", "",
                    "| k | subdomains | H/h | n | m | coarse | Iter | n_A | n_A / first | "
                    "assembly | factorization | coarse | solve | total | total / floor | "
                    "peak MiB/rank | runs |",
                    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"])
        for r in sel:
            hh = int(r["k"]) // (int(r["a"]) if not series.startswith("paper") else 1)
            out.append(f"| {r['k']} | {r['n_subdomains']} | {hh} | {r['n']} | {r['m']} | "
                       f"{r['coarse']} | {r['iter']} | {r['n_A']} | "
                       f"{float(r['n_A']) / n_a0:.2f} | {g(r['assembly'])} | "
                       f"{g(r['factorization'])} | {g(r['coarse_problem'])} | {g(r['solve'])} | "
                       f"{g(r['total'])} | {float(r['floor_ratio']):.2f} | "
                       f"{float(r['peak_mib']):.0f} | {r['runs']} |")
        out.append("")

    titles = {"weak": "Fixed H/h (c × c × c cells per subdomain)",
              "paper": "The paper's setting: three subdomains, h → 0",
              "coarse": "Coarse problem against the number of subdomains (c = 2)"}
    for base, title in titles.items():
        for suffix in variant_suffixes(contact, base):
            table(f"{title}{variant_note(suffix)}, one rank", base + suffix, 1)

    for suffix in variant_suffixes(contact, "weak"):
        mpi_tables(out, contact, "weak" + suffix, variant_note(suffix))
    for suffix in variant_suffixes(contact, "pair"):
        if not suffix.startswith("_alone"):
            pair_table(out, contact, suffix)

    if linear:
        out.extend(["### One monolithic linear solve (CHOLMOD, undecomposed brick, one rank)", "",
                    "| k | n | linear: assembly | factorization | solve | total | entries of L | "
                    "peak MiB | relative residual |",
                    "|---|---|---|---|---|---|---|---|---|"])
        for a, r in sorted(linear.items()):
            entries = f"{float(r['factor_entries']):.3g}" if r.get("factor_entries") else ""
            out.append(f"| {r['k']} | {r['n']} | {g(r['assembly'])} | {g(r['factorization'])} | "
                       f"{g(r['solve'])} | {g(r['linear_total'])} | {entries} | "
                       f"{float(r['peak_mib']):.0f} | {float(r['residual']):.1e} |")
        out.append("")
    with open(md_path, "w") as f:
        f.write("\n".join(out))


def plot(csv_path, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = load(csv_path)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for series, label, marker in [("weak", "fixed H/h", "o"), ("paper", "3 subdomains", "s"),
                                  ("weak_pcg", "fixed H/h, projected CG expansion", "^"),
                                  ("weak_max", "fixed H/h, Hessian norm bound max", "v"),
                                  ("weak_pcg_max", "fixed H/h, projected CG, bound max", "D"),
                                  ("weak_pcg_max_c0.001_r0.1",
                                   "fixed H/h, four options (+ MSA factor 0.001, "
                                   "recursive gradient 0.1)", "P"),
                                  ("weak_pcg_max_c0.001_r0.1_md",
                                   "fixed H/h, five options (+ arc scale mean diagonal)", "X"),
                                  ("weak_pcg_max_c0.001_r0.1_md_f3",
                                   "fixed H/h, the defaults with penalty factor 3", "*"),
                                  ("weak_pcg_max_c0.001_r0.1_md",
                                   "fixed H/h, the defaults", "p")]:
        sel = sorted([r for r in rows if r["series"] == series and r["np"] == "1"],
                     key=lambda r: int(r["n"]))
        if sel:
            axes[0].semilogx([int(r["n"]) for r in sel], [int(r["n_A"]) for r in sel],
                             marker=marker, label=label)
    axes[0].set_xlabel("primal unknowns n")
    axes[0].set_ylabel("n_A (multiplications by F)")
    axes[0].set_ylim(bottom=0)
    axes[0].legend(fontsize="small")
    axes[0].set_title("Numerical scalability (μ = 0.3, MPGP)")
    for series, label, marker in [("coarse", "2 × 2 × 2 cubes per subdomain", "o"),
                                  ("weak", "8 × 8 × 8 cubes per subdomain", "s")]:
        sel = sorted([r for r in rows if r["series"] == series and r["np"] == "1"],
                     key=lambda r: int(r["n_subdomains"]))
        if sel:
            axes[1].loglog([int(r["n_subdomains"]) for r in sel],
                           [float(r["coarse_problem"]) for r in sel], marker=marker, label=label)
    sel = sorted([r for r in rows if r["series"] == "coarse"], key=lambda r: int(r["n_subdomains"]))
    if sel:
        # A line ∝ N_s through the largest "coarse" point, for the eye.
        n_max, t_max = int(sel[-1]["n_subdomains"]), float(sel[-1]["coarse_problem"])
        axes[1].loglog([10, n_max], [t_max * 10 / n_max, t_max], "k--", label="∝ subdomains")
    axes[1].set_xlabel("subdomains")
    axes[1].set_ylabel("time [s]")
    axes[1].legend()
    axes[1].set_title("Setting up the coarse problem (phase coarse_problem)")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


def main():
    if "--plot" in sys.argv:
        i = sys.argv.index("--plot")
        plot(sys.argv[i + 1], sys.argv[i + 2])
        return
    arguments(__doc__, ["--exe", "--monolithic", "--cells-per-subdomain", "--a", "--np",
                        "--paper-k", "--coarse-a", "--repeats", "--csv", "--linear-csv",
                        "--markdown", "--expansion", "--hessian-norm-bound", "--inexact-msa-factor",
                        "--recursive-gradient-tolerance", "--arc-scale",
                        "--penalty-factor", "--multiplier-step",
                        "--add-summary",
                        "--pair-a"],
              ["--merge", "--report-only", "--linear-only", "--alternate"])
    exe = option("--exe", "build/feticontact")
    mono = option("--monolithic", "")
    c = int(option("--cells-per-subdomain", "8"))
    a_list = [int(v) for v in option("--a", "1,2,3,4,5,6").split(",") if v]
    ranks = [int(v) for v in option("--np", "1,2").split(",") if v]
    paper_k = [int(v) for v in option("--paper-k", "8,16").split(",") if v]
    coarse_a = [int(v) for v in option("--coarse-a", "1,3,5,7").split(",") if v]
    repeats = int(option("--repeats", "1"))
    csv_path = option("--csv", "doc/reports/data/scaling.csv")
    linear_path = option("--linear-csv", "doc/reports/data/scaling_linear.csv")
    md_path = option("--markdown", "doc/reports/data/scaling.md")
    command = "python3 " + " ".join(sys.argv)
    merge = "--merge" in sys.argv or "--report-only" in sys.argv
    rows = load(csv_path) if merge and os.path.exists(csv_path) else []
    linear = load(linear_path) if merge and os.path.exists(linear_path) else []
    if "--report-only" in sys.argv:
        report(rows + linear, md_path, command)
        return
    expansion = option("--expansion", "fixed")
    bound = option("--hessian-norm-bound", "sum")
    msa_factor = option("--inexact-msa-factor", "")
    recursive = option("--recursive-gradient-tolerance", "")
    arc_scale = option("--arc-scale", "norm")
    if arc_scale not in ("norm", "mean diagonal"):
        raise SystemExit(f"--arc-scale: unknown '{arc_scale}' (norm, mean diagonal)")
    penalty_norm = ""  # the removed penalty against ‖F‖ left this field of the variant unused
    factor = option("--penalty-factor", "")
    step = option("--multiplier-step", "")
    variant = (expansion, bound, msa_factor, recursive, arc_scale, penalty_norm, factor, step)
    short = {"fixed": "", "projected cg": "_pcg"}
    if expansion not in short:
        raise SystemExit(f"--expansion: unknown '{expansion}' ({', '.join(short)})")
    suffix = short[expansion] + ("" if bound == "sum" else "_" + bound) + \
        (f"_c{msa_factor}" if msa_factor else "") + (f"_r{recursive}" if recursive else "") + \
        ("_md" if arc_scale == "mean diagonal" else "") + \
        (f"_f{factor}" if factor else "") + (f"_s{step}" if step else "")

    def add(row):
        table, path, fields = (linear, linear_path, MONO_FIELDS) if row["series"] == "linear" \
            else (rows, csv_path, FIELDS)
        if merge and os.path.exists(path):
            # Rows that another study wrote into the same CSV since this one started stay.
            mine = {key(r) for r in table}
            table[:] = table + [r for r in load(path) if key(r) not in mine]
        table[:] = [r for r in table if key(r) != key(row)] + [row]
        save(path, table, fields)
        report(rows + linear, md_path, command)
        print({x: row[x] for x in row if x in ("series", "a", "k", "np", "n", "n_A", "total",
                                                "linear_total", "peak_mib")}, flush=True)

    if "--pair-a" in sys.argv:
        for a in [int(v) for v in option("--pair-a", "").split(",") if v]:
            for row in run_pair(exe, a, c, a * c, (3 * a, a, a), repeats, variant, suffix):
                add(row)
        return
    if "--add-summary" in sys.argv:
        series, a, c, p, path = option("--add-summary", "").split(",", 4)
        with open(path) as f:
            add(row_from_summaries([json.load(f)], series, int(a), int(c), int(a) * int(c),
                                   int(p)))
        return
    for a in a_list:
        if "--linear-only" not in sys.argv:
            if "--alternate" in sys.argv:
                for row in run_contact_interleaved(exe, "weak" + suffix, a, c, a * c,
                                                   (3 * a, a, a), ranks, repeats, variant):
                    add(row)
            else:
                for p in ranks:
                    add(run_contact(exe, "weak" + suffix, a, c, a * c, (3 * a, a, a), p,
                                    repeats, variant))
        if mono:
            add(run_monolithic(mono, a, c, a * c))
    if "--linear-only" in sys.argv:
        return
    for k in paper_k:
        add(run_contact(exe, "paper" + suffix, k, k, k, (3, 1, 1), 1, repeats, variant))
    for a in coarse_a:
        add(run_contact(exe, "coarse" + suffix, a, 2, 2 * a, (3 * a, a, a), 1, repeats,
                        variant))


if __name__ == "__main__":
    main()
