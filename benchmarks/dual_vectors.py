#!/usr/bin/env python3
"""Replicated against distributed dual vectors (`FETI/Dual vectors`), side by side.

    /usr/bin/python3 benchmarks/dual_vectors.py [--exe build/feticontact] [--np 1,2]
        [--repeats 3] [--csv doc/reports/data/dual_vectors.csv] [--markdown doc/reports/data/dual_vectors.md]
        [--report-only]

Every case runs with both settings in alternation, --repeats times, on every number of ranks of
--np (under `mpirun --oversubscribe`, OPENBLAS_NUM_THREADS=1). From summary.json: the median
time of the solve (`times.solve`), the Hessian multiplications (`hessian_multiplications.total`,
or the projected CG iterations of a scene without contact), the largest peak memory of a rank,
and the values each rank receives per application of F (`communication`: the slots, plus the
gathered row sums with replicated vectors or the ghost rows with distributed ones). The two
settings round the sums differently, so their counts may differ; the time per multiplication
compares the work. The CSV is rewritten after every case; --report-only writes the table from
it. Standard library only.
"""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from runs import collect_rows, summary_of_run, write_table  # noqa: E402

arguments(__doc__, ["--exe", "--np", "--repeats", "--csv", "--markdown"], ["--report-only"])

EXE = option("--exe", "build/feticontact")
NP = [int(n) for n in option("--np", "1,2").split(",")]
REPEATS = int(option("--repeats", "3"))
CSV = option("--csv", "doc/reports/data/dual_vectors.csv")
MD = option("--markdown", "doc/reports/data/dual_vectors.md")
FIELDS = ["case", "np", "vectors", "m_total", "count", "solve_s", "per_count_ms",
          "peak_rss_mib_max", "received_per_F_max"]
QUIET = ["Output/Write vtu=false"]
CASES = [
    ("brick k = 32, 48 blocks, no contact", "prm/brick.prm",
     ["Body 1/Mesh/Subdivisions=96, 32, 32", "Body 1/Decomposition/Method=blocks",
      "Body 1/Decomposition/Blocks=12, 4, 4", "Verification/Compare with monolithic solve=false"]),
    ("brick_contact k = 16, 32 blocks", "prm/brick_contact.prm",
     ["Body 1/Mesh/Subdivisions=48, 16, 16", "Body 1/Decomposition/Method=blocks",
      "Body 1/Decomposition/Blocks=8, 2, 2"]),
    ("cattaneo_mindlin", "prm/cattaneo_mindlin.prm", []),
]


def received(s, vectors):
    c = s["communication"]
    extra = c["ghosts_received_per_rank"] if vectors == "distributed" else \
        c["gathered_values_per_rank"]
    return max(a + b for a, b in zip(c["slots_received_per_rank"], extra))


def measure(name, prm, settings, np_):
    runs = {"replicated": [], "distributed": []}
    for _ in range(REPEATS):
        for vectors in runs:
            runs[vectors].append(summary_of_run(
                EXE, prm, settings + QUIET + [f"FETI/Dual vectors={vectors}"], np=np_,
                env={"OPENBLAS_NUM_THREADS": "1"}))
    rows = []
    for vectors, summaries in runs.items():
        s = summaries[0]
        count = s["hessian_multiplications"]["total"] or s["iterations"]
        solve = statistics.median(x["times"]["solve"] for x in summaries)
        rows.append({"case": name, "np": np_, "vectors": vectors, "m_total": s["m_total"],
                     "count": count, "solve_s": round(solve, 3),
                     "per_count_ms": round(1000 * solve / count, 3),
                     "peak_rss_mib_max": round(max(
                         max(x["memory"]["peak_rss_mib_per_rank"]) for x in summaries)),
                     "received_per_F_max": received(s, vectors)})
    return rows



def write_markdown(rows):
    lines = [f"Medians of {REPEATS} runs in alternation, OPENBLAS_NUM_THREADS=1 "
             "(`/usr/bin/python3 benchmarks/dual_vectors.py`). Count: Hessian multiplications "
             "(n_A), or projected CG iterations without contact.", "",
             "| case | ranks | dual unknowns | dual vectors | count | solve [s] | "
             "per count [ms] | distributed / replicated per count | peak memory per rank "
             "[MiB] | values received per F per rank |", "|---|---|---|---|---|---|---|---|---|---|"]
    by_key = {(r["case"], str(r["np"]), r["vectors"]): r for r in rows}
    for r in rows:
        other = by_key.get((r["case"], str(r["np"]), "replicated"))
        ratio = (f"{float(r['per_count_ms']) / float(other['per_count_ms']):.2f}"
                 if r["vectors"] == "distributed" and other else "")
        lines.append(f"| {r['case']} | {r['np']} | {int(r['m_total']):,} | {r['vectors']} | "
                     f"{r['count']} | {float(r['solve_s']):.2f} | {r['per_count_ms']} | "
                     f"{ratio} | {r['peak_rss_mib_max']} | {int(r['received_per_F_max']):,} |")
    write_table(MD, lines)


write_markdown(collect_rows(CSV, FIELDS, [
    lambda case=case, n=n: measure(*case, n) for case in CASES for n in NP]))
