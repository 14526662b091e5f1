#!/usr/bin/env python3
"""What one application of F exchanges, and the peak memory of every rank, on 1 … 16 ranks at
a fixed global size.

    python3 benchmarks/communication.py [--exe build/feticontact] [--prm prm/brick_contact.prm]
        [--k 16] [--blocks 8,2,2] [--np 1,2,4,8,16] [--dual-vectors replicated]
        [--csv doc/reports/data/communication.csv] [--markdown doc/reports/data/communication.md] [--report-only]

Every case runs the program once on `mpirun -np N --oversubscribe` (one MSA step: the volumes
and the memory do not depend on the number of iterations) and reads from summary.json, per
rank (`communication.*_per_rank`, `memory.peak_rss_mib_per_rank`):

- the slots: terms B_i u_i of rows that another rank adds up, exchanged point to point (both
  kinds of dual vectors), and the number of ranks this rank exchanges them with;
- replicated dual vectors: the other ranks' row sums that every rank receives (MPI_Allgatherv);
- distributed dual vectors: the ghost rows a rank imports (point to point) and from how many
  ranks;
- the values received per application of F on either kind (slots + gathered or + ghosts);
- the peak resident memory, the memory of the meshes that a rank holds (`memory.meshes_mib`;
  whole with replicated dual vectors, the rank's own cells with distributed ones), and of the
  contact nodes and surfaces, which every rank holds whole (`memory.contact_mib`).

--dual-vectors sets `FETI/Dual vectors` (the exchanges are counted for both kinds either way;
the memory is that of the setting).

The table gives the largest value over the ranks (and the smallest for the memory). The CSV is
rewritten after every case; --report-only writes the table from it. Standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from runs import collect_rows, summary_of_run, write_table  # noqa: E402

arguments(__doc__, ["--exe", "--prm", "--k", "--blocks", "--np", "--dual-vectors", "--csv",
                    "--markdown"],
          ["--report-only"])

EXE = option("--exe", "build/feticontact")
PRM = option("--prm", "prm/brick_contact.prm")
K = int(option("--k", "16"))
BLOCKS = option("--blocks", "8,2,2")
NP = [int(n) for n in option("--np", "1,2,4,8,16").split(",")]
DUAL_VECTORS = option("--dual-vectors", "replicated")
CSV = option("--csv", "doc/reports/data/communication.csv")
MD = option("--markdown", "doc/reports/data/communication.md")

FIELDS = ["np", "m_total", "n_subdomains", "slot_neighbours_max", "slots_received_max",
          "gathered_values_max", "ghost_neighbours_max", "ghosts_received_max",
          "replicated_received_max", "distributed_received_max", "peak_rss_mib_max",
          "peak_rss_mib_min", "meshes_mib", "contact_mib"]


def run(np_):
    """One run on np_ ranks: the row of the table."""
    s = summary_of_run(EXE, PRM, ["Body 1/Mesh/Subdivisions=%d, %d, %d" % (3 * K, K, K),
                                  "Body 1/Decomposition/Method=blocks",
                                  "Body 1/Decomposition/Blocks=" + BLOCKS.replace(",", ", "),
                                  "Contact solver/Maximum MSA iterations=1",
                                  "Output/Write vtu=false",
                                  "FETI/Dual vectors=" + DUAL_VECTORS], np=np_)
    c, m = s["communication"], s["memory"]["peak_rss_mib_per_rank"]
    replicated = [a + b for a, b in zip(c["slots_received_per_rank"],
                                        c["gathered_values_per_rank"])]
    distributed = [a + b for a, b in zip(c["slots_received_per_rank"],
                                         c["ghosts_received_per_rank"])]
    return {"np": np_, "m_total": s["m_total"], "n_subdomains": s["n_subdomains"],
            "slot_neighbours_max": int(max(c["slot_neighbours_per_rank"])),
            "slots_received_max": int(max(c["slots_received_per_rank"])),
            "gathered_values_max": int(max(c["gathered_values_per_rank"])),
            "ghost_neighbours_max": int(max(c["ghost_neighbours_per_rank"])),
            "ghosts_received_max": int(max(c["ghosts_received_per_rank"])),
            "replicated_received_max": int(max(replicated)),
            "distributed_received_max": int(max(distributed)),
            "peak_rss_mib_max": round(max(m)), "peak_rss_mib_min": round(min(m)),
            "meshes_mib": round(s["memory"]["meshes_mib"], 1),
            "contact_mib": round(s["memory"]["contact_mib"], 2)}


def write_markdown(rows):
    lines = ["Brick `%s`, Subdivisions %d, %d, %d, blocks %s (%s subdomains, m = %s dual "
             "unknowns), %s dual vectors; values per application of F, the largest over the "
             "ranks (`python3 benchmarks/communication.py`)." % (
                 PRM, 3 * K, K, K, BLOCKS, rows[0]["n_subdomains"], rows[0]["m_total"],
                 DUAL_VECTORS),
             "",
             "| np | slot neighbours | slots received | replicated: row sums gathered | "
             "distributed: ghost neighbours | ghosts received | received per F, replicated | "
             "received per F, distributed | peak memory per rank [MiB] | meshes [MiB] | "
             "contact nodes and surfaces [MiB] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s–%s | %s | %s |" % (
            r["np"], r["slot_neighbours_max"], r["slots_received_max"],
            r["gathered_values_max"], r["ghost_neighbours_max"], r["ghosts_received_max"],
            r["replicated_received_max"], r["distributed_received_max"],
            r["peak_rss_mib_min"], r["peak_rss_mib_max"], r["meshes_mib"],
            r.get("contact_mib", "–")))
    write_table(MD, lines)


write_markdown(collect_rows(CSV, FIELDS, [lambda n=n: [run(n)] for n in NP]))
