#!/usr/bin/env python3
"""A model of one multiplication by the Hessian and of the memory per rank up to 10⁴ ranks, from
costs measured on this machine.

    /usr/bin/python3 benchmarks/parallel_model.py [--exe build/feticontact]
        [--mpi-costs build/benchmarks/mpi_costs] [--h 8,16] [--dofs-per-rank 100000]
        [--ranks 1,10,100,1000,10000] [--reductions 7.8] [--latency-factor 1,10]
        [--ranks-per-node 32] [--repeats 3]
        [--communication doc/reports/data/communication.csv] [--coarse doc/reports/data/coarse_problem.csv]
        [--csv doc/reports/data/parallel_model.csv] [--markdown doc/reports/data/parallel_model.md]
        [--report-only]

Measured here, each the median of --repeats rounds (the CSV keeps them; --report-only rebuilds
the tables from it):

- `mpi_costs` on 2 ranks: the time of a global reduction t_r (ExactSum::sum_over_ranks, the sums
  over the rows of the dual vectors, which the ranks share out), the latency α and the time per
  value 1/β of a message between two ranks (a fit of the messages of 1 … 10⁵ doubles);
- per subdomain of H/h cubes across (H/h in --h; the brick of prm/brick_contact.prm in 6 × 2 × 2
  blocks, one rank, one MSA step): the local work of the applications of F per multiplication
  (`times.hessian_local_slowest_rank` / n_A / subdomains; a multiplication applies F
  f_F = `hessian_multiplications.F_applications` / n_A times)
  and the QP's vector work per multiplication (`times.qp_bookkeeping` / n_A / subdomains), and
  the peak memory per subdomain above the program's floor (the peak of the run minus that of
  the same run with 1 × 1 × 1 cubes, divided by the subdomains);
  (the coarse memory above the peak of its smallest case, 64 subdomains);
- from --communication (benchmarks/communication.py): the values a rank receives per
  application of F (slots and ghost rows), V = c s^(2/3) fitted over the rows with two or
  more subdomains per rank (s subdomains per rank, scaled by their interface: × (H/h / 8)²);
- from --coarse (benchmarks/coarse_problem.py): one solve with the factor of GGᵀ and the peak
  memory of rank 0 for the replicated factorization, fitted as a N_s^b on the three largest
  sizes;
- the check: the same brick on 2 ranks (a core each), its time per multiplication
  (`times.solve` / n_A) against the model's prediction for 2 ranks with its s and N_s.

--reductions: global reductions per multiplication (unit.distributed_qp_mpi prints them for
MPGP and SMALBE on distributed vectors: 6.5 and 7.7–7.8). The model at P ranks, each with
--dofs-per-rank unknowns in s = dofs / (3 (H/h + 1)³) subdomains (weak scaling; N_s = P s):

  t = s (t_F + t_QP) + f_F (n_nb α + V/β) + r t_r ⌈log₂ P⌉ + 2 (⌈log₂ P⌉ α + 6 N_s/β + t_c(N_s))

with n_nb = min(P − 1, 26) neighbours, one exchange of interface values per application of F, r
reductions of one tree each, and two applications of the coarse projector per multiplication
(PFP), each gathering the coarse vector (6 N_s values) on every rank and solving with the
replicated factor. --latency-factor multiplies α and t_r (a network's latency is not measured
here: shared memory is the fastest case). Memory per rank: s m_s plus the replicated coarse
factor m_c(N_s); per node of --ranks-per-node ranks R: R s m_s + R m_c(N_s) with the factor per
rank (FETI/Coarse factor = per rank), R s m_s + m_c(N_s) with the factor per node (the
default). Standard library only.
"""
import csv
import math
import statistics
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli import arguments, option  # noqa: E402
from runs import summary_of_run  # noqa: E402

arguments(__doc__, ["--exe", "--mpi-costs", "--h", "--dofs-per-rank", "--ranks", "--reductions",
                    "--latency-factor", "--ranks-per-node", "--repeats", "--communication", "--coarse", "--csv",
                    "--markdown"],
          ["--report-only"])

EXE = option("--exe", "build/feticontact")
MPI_COSTS = option("--mpi-costs", "build/benchmarks/mpi_costs")
H = [int(h) for h in option("--h", "8,16").split(",")]
DOFS = float(option("--dofs-per-rank", "100000"))
RANKS = [int(p) for p in option("--ranks", "1,10,100,1000,10000").split(",")]
REDUCTIONS = float(option("--reductions", "7.8"))
LATENCY = [float(f) for f in option("--latency-factor", "1,10").split(",")]
PER_NODE = int(option("--ranks-per-node", "32"))
REPEATS = int(option("--repeats", "3"))
COMMUNICATION = option("--communication", "doc/reports/data/communication.csv")
COARSE = option("--coarse", "doc/reports/data/coarse_problem.csv")
CSV = option("--csv", "doc/reports/data/parallel_model.csv")
MARKDOWN = option("--markdown", "doc/reports/data/parallel_model.md")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OPENBLAS_NUM_THREADS="1", DEAL_II_NUM_THREADS="1")


def mpi_costs():
    result = subprocess.run(["mpirun", "-np", "2", MPI_COSTS], env=ENV, capture_output=True,
                            text=True, check=True)
    rows = [line.split(",") for line in result.stdout.split()]
    costs = {"reduction": next(float(r[3]) for r in rows if r[1] == "exact_sum")}
    messages = [(float(r[2]), float(r[3])) for r in rows if r[1] == "message"]
    # Least squares t = α + v/β.
    n = len(messages)
    mv = sum(v for v, _ in messages) / n
    mt = sum(t for _, t in messages) / n
    slope = (sum((v - mv) * (t - mt) for v, t in messages) /
             sum((v - mv) ** 2 for v, _ in messages))
    costs["per_value"] = slope
    costs["latency"] = max(min(t for v, t in messages if v == min(w for w, _ in messages)), 0.0)
    return costs


def run_brick(cubes, np=None):
    """One MSA step of the brick in 6 × 2 × 2 blocks (cubes: cells per block edge), on one rank
    or under mpirun -np np."""
    return summary_of_run(EXE, "prm/brick_contact.prm",
                          [f"Body 1/Mesh/Subdivisions={6 * cubes}, {2 * cubes}, {2 * cubes}",
                           "Body 1/Decomposition/Method=blocks",
                           "Body 1/Decomposition/Blocks=6, 2, 2",
                           "Contact solver/Maximum MSA iterations=1",
                           "Output/Write vtu=false"],
                          np=np, env={"OPENBLAS_NUM_THREADS": "1", "DEAL_II_NUM_THREADS": "1"})


def subdomain_costs(h):
    s = run_brick(h)
    floor = run_brick(1)
    two = run_brick(h, np=2)
    n_s = s["n_subdomains"]
    t = s["times"]
    n_A = s["hessian_multiplications"]["total"]
    return {"t_F": t["hessian_local_slowest_rank"] / n_A / n_s,
            "f_F": s["hessian_multiplications"]["F_applications"] / n_A,
            "t_QP": t["qp_bookkeeping"] / n_A / n_s,
            "m_s": (s["memory"]["peak_rss_mib_max"] - floor["memory"]["peak_rss_mib_max"]) / n_s,
            "dofs": s["n_primal"] / n_s,
            "measured_2_ranks": two["times"]["solve"] / two["hessian_multiplications"]["total"],
            "n_subdomains": n_s}


def power_fit(points):
    """a, b of y = a x^b by least squares in logarithms."""
    xs = [math.log(x) for x, _ in points]
    ys = [math.log(y) for _, y in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return math.exp(my - b * mx), b


def coarse_fits():
    with open(COARSE) as f:
        rows = [r for r in csv.DictReader(f) if r["method"] == "replicated" and r["ranks"] == "1"]
    rows.sort(key=lambda r: int(r["subdomains"]))
    last = rows[-3:]
    solve = power_fit([(int(r["subdomains"]), float(r["solve_seconds"])) for r in last])
    floor = min(float(r["peak_mib_rank0"]) for r in rows)  # the program with the smallest case
    memory = power_fit([(int(r["subdomains"]), float(r["peak_mib_rank0"]) - floor) for r in last])
    return solve, memory


def volume_fit():
    with open(COMMUNICATION) as f:
        rows = [r for r in csv.DictReader(f) if int(r["np"]) > 1]
    # received_max; distributed_received_max in a CSV written while the dual vectors could still
    # be replicated.
    points = [(int(r["n_subdomains"]) / int(r["np"]),
               float(r.get("received_max") or r["distributed_received_max"]))
              for r in rows if int(r["n_subdomains"]) / int(r["np"]) >= 2]
    # V = c s^(2/3): c by least squares.
    return (sum(v * s ** (2 / 3) for s, v in points) /
            sum(s ** (4 / 3) for s, _ in points))


def measure():
    """Every quantity the median of --repeats rounds (this machine's speed varies by 15 % and
    more between runs)."""
    rounds = []
    for _ in range(REPEATS):
        values = {}
        values.update(mpi_costs())
        for h in H:
            for key, v in subdomain_costs(h).items():
                values[f"{key}_h{h}"] = v
        print(values, flush=True)
        rounds.append(values)
    values = {key: statistics.median(r[key] for r in rounds) for key in rounds[0]}
    with open(CSV, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["quantity", "value"])
        for key, v in values.items():
            writer.writerow([key, v])


PARTS = ("local", "exchange", "reductions", "coarse")


def model_parts(values, h, p, s, alpha, t_r, c_volume, solve_a, solve_b):
    """The model's time per multiplication at p ranks with s subdomains of H/h = h each, by part."""
    n_s = p * s
    log_p = math.ceil(math.log2(p)) if p > 1 else 0
    volume = c_volume * s ** (2 / 3) * (h / 8) ** 2 if p > 1 else 0
    return {"local": s * (values[f"t_F_h{h}"] + values[f"t_QP_h{h}"]),
            "exchange": values.get(f"f_F_h{h}", 1.0) *
            (min(p - 1, 26) * alpha + volume * values["per_value"]) if p > 1 else 0,
            "reductions": REDUCTIONS * t_r * log_p,
            "coarse": 2 * (log_p * alpha + 6 * n_s * values["per_value"] * (p > 1) +
                           solve_a * n_s ** solve_b)}


def report():
    with open(CSV) as f:
        values = {r["quantity"]: float(r["value"]) for r in csv.DictReader(f)}
    (solve_a, solve_b), (mem_a, mem_b) = coarse_fits()
    c_volume = volume_fit()
    lines = ["<!-- written by benchmarks/parallel_model.py -->", "",
             f"Measured: global reduction t_r = {values['reduction'] * 1e6:.2f} µs, message "
             f"latency α = {values['latency'] * 1e6:.2f} µs and {values['per_value'] * 1e9:.2f} ns "
             f"per value (2 ranks, shared memory); replicated coarse solve "
             f"t_c = {solve_a:.3g} N_s^{solve_b:.2f} s and factor memory "
             f"m_c = {mem_a:.3g} N_s^{mem_b:.2f} MiB (doc/reports/data/coarse_problem.csv); interface "
             f"values per application of F V = {c_volume:.0f} s^(2/3) × (H/h / 8)²; "
             f"{REDUCTIONS:g} reductions per multiplication.", "",
             "| H/h | DoFs per subdomain | applications of F per multiplication f_F "
             "| local F per subdomain and multiplication [ms] | QP work per subdomain [ms] "
             "| memory per subdomain [MiB] |", "|---|---|---|---|---|---|"]
    for h in H:
        lines.append(f"| {h} | {values[f'dofs_h{h}']:,.0f} | {values.get(f'f_F_h{h}', 1):.2f} | "
                     f"{values[f't_F_h{h}'] * 1e3:.3f} | {values[f't_QP_h{h}'] * 1e3:.3f} | "
                     f"{values[f'm_s_h{h}']:.2f} |")
    lines += ["", "Check on 2 ranks (the brick in 6 × 2 × 2 blocks, a core per rank): time per "
              "multiplication measured (`times.solve` / n_A) against the model with the run's s "
              "and N_s:", "", "| H/h | subdomains per rank s | measured [ms] | model [ms] |",
              "|---|---|---|---|"]
    for h in H:
        if f"measured_2_ranks_h{h}" not in values:
            continue
        s2 = values[f"n_subdomains_h{h}"] / 2
        model = sum(model_parts(values, h, 2, s2, values["latency"], values["reduction"],
                                c_volume, solve_a, solve_b).values())
        lines.append(f"| {h} | {s2:g} | {values[f'measured_2_ranks_h{h}'] * 1e3:.3g} | "
                     f"{model * 1e3:.3g} |")
    lines += ["", f"Per multiplication at {DOFS:,.0f} unknowns per rank (weak scaling; "
                  f"10⁹ unknowns at 10⁴ ranks):", "",
              "| H/h | latency × | ranks | subdomains N_s | local [ms] | exchange [ms] | "
              "reductions [ms] | coarse [ms] | total [ms] | largest part | memory per rank, "
              f"subdomains + coarse factor [MiB] | memory per node of {PER_NODE} ranks, "
              "coarse factor per rank / per node [GiB] |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows = []
    for h in H:
        per_subdomain = 3 * (h + 1) ** 3
        s = DOFS / per_subdomain
        for factor in LATENCY:
            alpha = values["latency"] * factor
            t_r = values["reduction"] * factor
            for p in RANKS:
                n_s = p * s
                parts = model_parts(values, h, p, s, alpha, t_r, c_volume, solve_a, solve_b)
                local, exchange, reductions, coarse = (parts[k] for k in PARTS)
                total = sum(parts.values())
                largest = max(parts, key=parts.get)
                memory = s * values[f"m_s_h{h}"] + mem_a * n_s ** mem_b
                node_ranks = min(p, PER_NODE)

                def node_gib(factors):
                    return (node_ranks * s * values[f"m_s_h{h}"] +
                            min(factors, node_ranks) * mem_a * n_s ** mem_b) / 1024
                rows.append((h, factor, p, n_s, parts, total, largest, memory))
                lines.append(f"| {h} | {factor:g} | {p:,} | {n_s:,.0f} | {local * 1e3:.3g} | "
                             f"{exchange * 1e3:.3g} | {reductions * 1e3:.3g} | "
                             f"{coarse * 1e3:.3g} | {total * 1e3:.3g} | {largest} | "
                             f"{s * values[f'm_s_h{h}']:,.0f} + {mem_a * n_s ** mem_b:,.0f} | "
                             f"{node_gib(PER_NODE):,.1f} / {node_gib(1):,.1f} |")
    with open(MARKDOWN, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    if "--report-only" not in sys.argv:
        measure()
    report()
