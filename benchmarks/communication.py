#!/usr/bin/env python3
"""What one application of F exchanges, and the peak memory of every rank, on 1 … 16 ranks at
a fixed global size.

    python3 benchmarks/communication.py [--exe build/feticontact] [--prm prm/brick_contact.prm]
        [--k 16] [--blocks 8,2,2] [--np 1,2,4,8,16]
        [--csv doc/reports/data/communication.csv] [--markdown doc/reports/data/communication.md] [--report-only]

Every case runs the program once on `mpirun -np N --oversubscribe` (one MSA step: the volumes
and the memory do not depend on the number of iterations) and reads from summary.json, per
rank (`communication.*_per_rank`, `memory.peak_rss_mib_per_rank`):

- the slots: terms B_i u_i of rows that another rank adds up, exchanged point to point, and the
  number of ranks this rank exchanges them with;
- the ghost rows of the dual vectors that a rank imports (point to point; every rank holds the
  rows it adds up) and from how many ranks;
- the values received per application of F (slots + ghosts);
- the peak resident memory, and the memory of the meshes (`memory.meshes_mib`: the cells of
  rank 0's subdomains) and of the contact nodes and surfaces (`memory.contact_mib`) of rank 0.

The table gives the largest value over the ranks (and the smallest for the memory). The CSV is
rewritten after every case; --report-only writes the table from it (in a CSV written while the
dual vectors could still be replicated, the values received are `distributed_received_max`).
Standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from runs import collect_rows, summary_of_run, write_table  # noqa: E402

arguments(__doc__, ["--exe", "--prm", "--k", "--blocks", "--np", "--csv", "--markdown"],
          ["--report-only"])

EXE = option("--exe", "build/feticontact")
PRM = option("--prm", "prm/brick_contact.prm")
K = int(option("--k", "16"))
BLOCKS = option("--blocks", "8,2,2")
NP = [int(n) for n in option("--np", "1,2,4,8,16").split(",")]
CSV = option("--csv", "doc/reports/data/communication.csv")
MD = option("--markdown", "doc/reports/data/communication.md")

FIELDS = ["np", "m_total", "n_subdomains", "slot_neighbours_max", "slots_received_max",
          "ghost_neighbours_max", "ghosts_received_max", "received_max", "peak_rss_mib_max",
          "peak_rss_mib_min", "meshes_mib", "contact_mib"]


def run(np_):
    """One run on np_ ranks: the row of the table."""
    s = summary_of_run(EXE, PRM, ["Body 1/Mesh/Subdivisions=%d, %d, %d" % (3 * K, K, K),
                                  "Body 1/Decomposition/Method=blocks",
                                  "Body 1/Decomposition/Blocks=" + BLOCKS.replace(",", ", "),
                                  "Contact solver/Maximum MSA iterations=1",
                                  "Output/Write vtu=false"], np=np_)
    c, m = s["communication"], s["memory"]["peak_rss_mib_per_rank"]
    received = [a + b for a, b in zip(c["slots_received_per_rank"],
                                      c["ghosts_received_per_rank"])]
    return {"np": np_, "m_total": s["m_total"], "n_subdomains": s["n_subdomains"],
            "slot_neighbours_max": int(max(c["slot_neighbours_per_rank"])),
            "slots_received_max": int(max(c["slots_received_per_rank"])),
            "ghost_neighbours_max": int(max(c["ghost_neighbours_per_rank"])),
            "ghosts_received_max": int(max(c["ghosts_received_per_rank"])),
            "received_max": int(max(received)),
            "peak_rss_mib_max": round(max(m)), "peak_rss_mib_min": round(min(m)),
            "meshes_mib": round(s["memory"]["meshes_mib"], 1),
            "contact_mib": round(s["memory"]["contact_mib"], 2)}


def write_markdown(rows):
    lines = ["Brick `%s`, Subdivisions %d, %d, %d, blocks %s (%s subdomains, m = %s dual "
             "unknowns); values per application of F, the largest over the ranks "
             "(`python3 benchmarks/communication.py`)." % (
                 PRM, 3 * K, K, K, BLOCKS, rows[0]["n_subdomains"], rows[0]["m_total"]),
             "",
             "| np | slot neighbours | slots received | ghost neighbours | ghosts received | "
             "received per F | peak memory per rank [MiB] | meshes [MiB] | "
             "contact nodes and surfaces [MiB] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s | %s | %s | %s–%s | %s | %s |" % (
            r["np"], r["slot_neighbours_max"], r["slots_received_max"],
            r["ghost_neighbours_max"], r["ghosts_received_max"],
            r.get("received_max", r.get("distributed_received_max")),
            r["peak_rss_mib_min"], r["peak_rss_mib_max"], r["meshes_mib"],
            r.get("contact_mib", "–")))
    write_table(MD, lines)


write_markdown(collect_rows(CSV, FIELDS, [lambda n=n: [run(n)] for n in NP]))
