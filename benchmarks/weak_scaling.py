#!/usr/bin/env python3
"""The peak memory per rank at a fixed size per rank (weak scaling) on 1 … 16 ranks.

    /usr/bin/python3 benchmarks/weak_scaling.py [--exe build/feticontact]
        [--prm prm/brick_contact.prm] [--cubes 16] [--np 1,2,4,8,16]
        [--csv doc/reports/data/weak_scaling.csv]
        [--markdown doc/reports/data/weak_scaling.md] [--report-only]

On np ranks the brick of --prm is a bar of np blocks of --cubes³ cubes (`Subdivisions =
np·C, C, C`, `Decomposition/Method = blocks`, `Blocks = np, 1, 1`): every rank holds one subdomain
of the same size. One MSA step (`Contact solver/Maximum MSA iterations = 1`: the meshes, the
factors and the QP vectors all exist by then), under `mpirun --oversubscribe`. From summary.json:
the unknowns, the largest and smallest peak resident memory over the ranks
(`memory.peak_rss_mib_per_rank`), the program's own estimate (`memory.estimated_peak_mib`) and
the memory of the mesh that rank 0 holds (`memory.meshes_mib`: the cells of its own block).
The table gives the largest peak against that of np = 1. The CSV is rewritten after every case;
--report-only writes the table from it. Standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from runs import collect_rows, summary_of_run, write_table  # noqa: E402

arguments(__doc__, ["--exe", "--prm", "--cubes", "--np", "--csv", "--markdown"],
          ["--report-only"])

EXE = option("--exe", "build/feticontact")
PRM = option("--prm", "prm/brick_contact.prm")
CUBES = int(option("--cubes", "16"))
NP = [int(n) for n in option("--np", "1,2,4,8,16").split(",")]
CSV = option("--csv", "doc/reports/data/weak_scaling.csv")
MD = option("--markdown", "doc/reports/data/weak_scaling.md")
FIELDS = ["np", "n_primal", "m_total", "peak_rss_mib_max", "peak_rss_mib_min", "estimated_mib",
          "meshes_mib"]


def run(np_):
    s = summary_of_run(EXE, PRM, [f"Body 1/Mesh/Subdivisions={CUBES * np_}, {CUBES}, {CUBES}",
                                  "Body 1/Decomposition/Method=blocks",
                                  f"Body 1/Decomposition/Blocks={np_}, 1, 1",
                                  "Contact solver/Maximum MSA iterations=1",
                                  "Output/Write vtu=false"],
                       np=np_, env={"OPENBLAS_NUM_THREADS": "1"})
    peaks = s["memory"]["peak_rss_mib_per_rank"]
    return {"np": np_, "n_primal": s["n_primal"], "m_total": s["m_total"],
            "peak_rss_mib_max": round(max(peaks)), "peak_rss_mib_min": round(min(peaks)),
            "estimated_mib": round(s["memory"]["estimated_peak_mib"]),
            "meshes_mib": round(s["memory"]["meshes_mib"], 1)}



def write_markdown(rows):
    base = float(rows[0]["peak_rss_mib_max"])
    lines = [f"Brick `{PRM}` as a bar of np blocks of {CUBES}³ cubes, one subdomain per rank "
             "(`/usr/bin/python3 benchmarks/weak_scaling.py`).", "",
             "| np | unknowns | dual unknowns | peak memory per rank [MiB] | largest / np = 1 | "
             "estimate [MiB] | meshes [MiB] |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['np']} | {int(r['n_primal']):,} | {int(r['m_total']):,} | "
                     f"{r['peak_rss_mib_min']}–{r['peak_rss_mib_max']} | "
                     f"{float(r['peak_rss_mib_max']) / base:.2f} | {r['estimated_mib']} | "
                     f"{r['meshes_mib']} |")
    write_table(MD, lines)


write_markdown(collect_rows(CSV, FIELDS, [lambda n=n: [run(n)] for n in NP]))
