// The QP layer on distributed vectors: ExactSum (the sum of a set of doubles, rounded once, in any
// order and any split among ranks), the reproducible reductions of DistributedVector on a
// ReproduciblePartitioner, and MPGP and SMALBE on them. Run on P ranks, the program solves the
// same problems on the first 1, 2, …, P ranks (the problem's unknowns spread over them by a
// scrambled assignment; a rank's entries keyed by their unknowns) and requires the same solution
// to the last bit and the same counts on every number of ranks, and the solution on one process
// with a plain deal.II partitioner (every term of a sum added exactly) within the solvers'
// tolerance.

#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/separable_set.h>
#include <feticontact/qp/smalbe.h>

#include "qp_test_problems.h"
#include "test_tools.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <type_traits>

using namespace dealii;
using namespace FetiContact;

namespace
{
  using namespace QPTestProblems;

  std::string
  one_decimal(const double v)
  {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << v;
    return s.str();
  }

  /** Whether two doubles are the same bits. */
  bool
  same_bits(const double a, const double b)
  {
    return std::memcmp(&a, &b, sizeof(double)) == 0;
  }

  void
  check_exact_sum(const MPI_Comm world)
  {
    {
      // Cancellation that a running sum loses: 1e100 + 1 − 1e100.
      ExactSum s;
      for (const double x : {1e100, 1., -1e100})
        s.add(x);
      check(s.value() == 1., "ExactSum: 1e100 + 1 − 1e100 = " + sci(s.value()));
    }
    {
      // Ten times 0.1 is 1 + 5.6e-17 exactly, which rounds to 1 (a running sum gives 1 − 1.1e-16).
      ExactSum s;
      for (unsigned int k = 0; k < 10; ++k)
        s.add(0.1);
      check(s.value() == 1., "ExactSum: ten times 0.1 rounds to 1");
    }
    {
      // A tie: 1 + 2^-53 is halfway between 1 and its successor; with a further 2^-1000 it is
      // above the half, so it rounds up (a sticky bit far below the leading 64 bits).
      ExactSum s, t;
      s.add(1.);
      s.add(std::ldexp(1., -53));
      t = s;
      t.add(std::ldexp(1., -1000));
      check(s.value() == 1. && t.value() == 1. + std::ldexp(1., -52),
            "ExactSum: ties to even, and a sticky bit 947 binary places below the half");
    }
    {
      // Subnormal and huge terms, negative sums, infinities and NaN.
      ExactSum s;
      s.add(std::numeric_limits<double>::denorm_min());
      s.add(-std::numeric_limits<double>::max());
      s.add(std::numeric_limits<double>::max());
      s.add(-3 * std::numeric_limits<double>::denorm_min());
      check(s.value() == -2 * std::numeric_limits<double>::denorm_min(),
            "ExactSum: subnormal terms beside ±max");
      ExactSum inf, nan;
      inf.add(1.);
      inf.add(std::numeric_limits<double>::infinity());
      nan.add(std::numeric_limits<double>::infinity());
      nan.add(-std::numeric_limits<double>::infinity());
      check(std::isinf(inf.value()) && inf.value() > 0 && std::isnan(nan.value()),
            "ExactSum: ∞ + 1 = ∞, ∞ − ∞ = NaN");
    }
    {
      // 10⁵ terms over 600 binary orders of magnitude: the same bits in any order, and on the
      // ranks of `world` each holding a different share.
      std::mt19937                           engine(11);
      std::uniform_real_distribution<double> mantissa(-1, 1);
      std::uniform_int_distribution<int>     exponent(-300, 300);
      std::vector<double>                    terms(100000);
      for (double &x : terms)
        x = std::ldexp(mantissa(engine), exponent(engine));
      ExactSum forward, backward;
      for (const double x : terms)
        forward.add(x);
      for (auto x = terms.rbegin(); x != terms.rend(); ++x)
        backward.add(*x);
      std::shuffle(terms.begin(), terms.end(), engine);
      ExactSum shuffled;
      for (const double x : terms)
        shuffled.add(x);
      const int rank = Utilities::MPI::this_mpi_process(world);
      const int size = Utilities::MPI::n_mpi_processes(world);
      ExactSum  share;
      for (std::size_t i = 0; i < terms.size(); ++i)
        if (int((i * 7919) % 13) % size == rank)
          share.add(terms[i]);
      share.sum_over_ranks(world);
      check(same_bits(forward.value(), backward.value()) &&
              same_bits(forward.value(), shuffled.value()) &&
              same_bits(forward.value(), share.value()),
            "ExactSum: 10⁵ terms in three orders and split among " + std::to_string(size) +
              " ranks give the same bits " + sci(forward.value()));
      // The exact sum of a few terms that a long double holds exactly.
      ExactSum small;
      for (const double x : {0.1, 0.2, 0.3})
        small.add(x);
      const double exact = static_cast<double>(0.1L + 0.2L + 0.3L);
      check(small.value() == exact,
            "ExactSum: 0.1 + 0.2 + 0.3 correctly rounded (" + sci(small.value()) + ")");
    }
  }

  /** A QP min ½xᵀAx − bᵀx s.t. x ∈ Ω, Gx = e with bounds, discs and free components. */
  struct GlobalProblem
  {
    unsigned int       n = 0;
    FullMatrix<double> A, G;
    Vector<double>     b, e;
    /** Lower bounds on 0 … n_lower − 1, discs on the pairs (n_lower + 2k, n_lower + 2k + 1). */
    unsigned int n_lower = 0, n_discs = 0;
    double       radius = 0;
  };

  GlobalProblem
  make_problem()
  {
    GlobalProblem p;
    p.n_lower = 24;
    p.n_discs = 12;
    p.n       = p.n_lower + 2 * p.n_discs + 16;
    p.radius  = 0.4;
    p.A       = random_spd(p.n, 1e3);
    p.b.reinit(p.n);
    for (auto &bi : p.b)
      bi = random_in(-20, 20);
    p.G.reinit(3, p.n);
    for (unsigned int r = 0; r < 3; ++r)
      for (unsigned int j = p.n_lower + 2 * p.n_discs; j < p.n; ++j)
        p.G(r, j) = random_in(-1, 1);
    p.e.reinit(3);
    for (auto &ei : p.e)
      ei = random_in(-1, 1);
    return p;
  }

  /**
   * The unknowns a rank holds: blocks of two consecutive ones, spread over @p n_ranks ranks
   * scrambled (no rank holds a contiguous range of unknowns), in increasing order (the keys of a
   * ReproduciblePartitioner's chunk increase).
   */
  std::vector<unsigned int>
  owned_indices(const unsigned int n, const unsigned int n_ranks, const unsigned int rank)
  {
    std::vector<unsigned int> owned;
    for (unsigned int i = 0; i < n; ++i)
      if (((i / 2) * 5 + 3) % 7 % n_ranks == rank)
        owned.push_back(i);
    return owned;
  }


  struct Solution
  {
    Vector<double> x, mu;
    unsigned int   iterations = 0, multiplications = 0, inner_iterations = 0;
    /** The global reductions of the vectors (ReproduciblePartitioner::n_reductions). */
    std::uint64_t reductions = 0;
    bool          converged  = false;
  };

  /** A set with the blocks of the problem on the entries that @p model's rank holds. */
  QP::SeparableSet
  local_set(const GlobalProblem &p, const std::vector<unsigned int> &global_index)
  {
    QP::SeparableSet set(global_index.size());
    std::vector<int> local(p.n, -1);
    for (unsigned int i = 0; i < global_index.size(); ++i)
      local[global_index[i]] = i;
    for (unsigned int i = 0; i < p.n_lower; ++i)
      if (local[i] >= 0)
        set.set_lower_bound(local[i], 0.);
    for (unsigned int k = 0; k < p.n_discs; ++k)
      {
        const unsigned int i = p.n_lower + 2 * k;
        if (local[i] >= 0)
          set.add_disc(local[i], local[i + 1], {{0., 0.}}, p.radius);
      }
    return set;
  }

  /** The number of global reductions made so far by the vectors of @p x's partitioner. */
  std::uint64_t
  n_reductions(const DistributedVector &x)
  {
    const ReproduciblePartitioner *p = ReproducibleReductions::partitioner_of(x);
    return p != nullptr ? p->n_reductions : 0;
  }

  /**
   * The problem on vectors like @p zero, whose owned entries are the unknowns @p global_index of
   * the problem.
   */
  using V = DistributedVector;
  Solution
  solve(const GlobalProblem             &p,
        const std::vector<unsigned int> &global_index,
        const V                         &zero,
        const bool                       with_equality)
  {
    const auto full_of = [&](const V &x) {
      Vector<double> full(p.n);
      for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
        full[global_index[i]] = x.local_element(i);
      Utilities::MPI::sum(full, x.get_mpi_communicator(), full);
      return full;
    };
    QP::Problem<V> problem;
    problem.hessian = [&](const V &x, V &y) {
      const Vector<double> full = full_of(x);
      y.reinit(x, true);
      for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
        {
          double s = 0;
          for (unsigned int j = 0; j < p.n; ++j)
            s += p.A(global_index[i], j) * full[j];
          y.local_element(i) = s;
        }
    };
    problem.linear_term = zero;
    for (unsigned int i = 0; i < global_index.size(); ++i)
      problem.linear_term.local_element(i) = p.b[global_index[i]];
    const QP::SeparableSet set = local_set(p, global_index);
    problem.set                = &set;
    if (with_equality)
      {
        problem.G = [&](const V &x, Vector<double> &y) {
          const Vector<double> full = full_of(x);
          y.reinit(p.G.m());
          p.G.vmult(y, full);
        };
        problem.Gt = [&](const Vector<double> &mu, V &y) {
          y.reinit(problem.linear_term, true);
          for (unsigned int i = 0; i < y.locally_owned_size(); ++i)
            {
              double s = 0;
              for (unsigned int r = 0; r < p.G.m(); ++r)
                s += p.G(r, global_index[i]) * mu[r];
              y.local_element(i) = s;
            }
        };
        problem.e = p.e;
      }
    Solution solution;
    V        x          = zero;
    solution.reductions = n_reductions(x);
    if (with_equality)
      {
        typename QP::SMALBE<V>::AdditionalData data;
        data.tolerance             = 1e-10;
        data.feasibility_tolerance = 1e-10;
        const auto report          = QP::SMALBE<V>(data).solve(problem, x, solution.mu);
        solution.iterations        = report.iterations;
        solution.inner_iterations  = report.inner_iterations;
        solution.multiplications   = report.hessian_multiplications;
        solution.converged         = report.converged;
      }
    else
      {
        typename QP::MPGP<V>::AdditionalData data;
        data.tolerance      = 1e-10 * QP::l2_norm(problem.linear_term);
        const auto report   = QP::MPGP<V>(data).solve(problem.hessian, problem.linear_term, set, x);
        solution.iterations = report.iterations;
        solution.multiplications = report.hessian_multiplications;
        solution.converged       = report.converged;
      }
    solution.reductions = n_reductions(x) - solution.reductions;
    solution.x          = full_of(x);
    return solution;
  }

  void
  check_solvers(const MPI_Comm world, const bool with_equality, const bool chunks)
  {
    const std::string name =
      std::string(with_equality ? "SMALBE" : "MPGP") + (chunks ? " (sums by chunks)" : "");
    const GlobalProblem p    = make_problem();
    const unsigned int  P    = Utilities::MPI::n_mpi_processes(world);
    const unsigned int  rank = Utilities::MPI::this_mpi_process(world);

    std::vector<unsigned int> all(p.n);
    std::iota(all.begin(), all.end(), 0);
    const Solution serial =
      solve(p, all, V(std::make_shared<const Utilities::MPI::Partitioner>(p.n)), with_equality);

    std::vector<Solution> on(P + 1);
    for (unsigned int n_ranks = 1; n_ranks <= P; ++n_ranks)
      {
        MPI_Comm comm;
        MPI_Comm_split(world, rank < n_ranks ? 0 : MPI_UNDEFINED, rank, &comm);
        if (comm == MPI_COMM_NULL)
          continue;
        // With chunks: the blocks of two consecutive indices, each on one rank.
        const std::vector<unsigned int> owned = owned_indices(p.n, n_ranks, rank);
        std::vector<unsigned int>       chunk_of_entry;
        if (chunks)
          for (const unsigned int i : owned)
            chunk_of_entry.push_back(i / 2);
        unsigned long long n_owned = owned.size(), first = 0;
        MPI_Exscan(&n_owned, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
        if (rank == 0)
          first = 0;
        const auto partitioner = std::make_shared<const ReproduciblePartitioner>(
          comm, first, p.n, IndexSet(p.n), owned, chunk_of_entry);
        on[n_ranks] = solve(p, owned, V(partitioner), with_equality);
        MPI_Comm_free(&comm);
      }
    if (rank != 0)
      return;
    Vector<double> difference(serial.x);
    difference -= on[1].x;
    check(on[1].converged && serial.converged &&
            difference.linfty_norm() <= 1e-8 * serial.x.linfty_norm(),
          name + " on 1 rank against a plain partitioner on one process: difference " +
            sci(difference.linfty_norm() / serial.x.linfty_norm()) + " (" +
            std::to_string(on[1].multiplications) + " and " +
            std::to_string(serial.multiplications) + " multiplications)");
    for (unsigned int n_ranks = 2; n_ranks <= P; ++n_ranks)
      {
        bool same = on[n_ranks].x.size() == on[1].x.size();
        for (unsigned int i = 0; same && i < on[1].x.size(); ++i)
          same = same_bits(on[n_ranks].x[i], on[1].x[i]);
        for (unsigned int r = 0; same && r < on[1].mu.size(); ++r)
          same = same_bits(on[n_ranks].mu[r], on[1].mu[r]);
        check(same && on[n_ranks].iterations == on[1].iterations &&
                on[n_ranks].inner_iterations == on[1].inner_iterations &&
                on[n_ranks].multiplications == on[1].multiplications &&
                on[n_ranks].reductions == on[1].reductions,
              name + " on " + std::to_string(n_ranks) +
                " ranks: the same bits and counts as on 1 rank (" +
                std::to_string(on[n_ranks].iterations) + " iterations, " +
                std::to_string(on[n_ranks].multiplications) + " multiplications, " +
                std::to_string(on[n_ranks].reductions) + " global reductions: " +
                one_decimal(double(on[n_ranks].reductions) / on[n_ranks].multiplications) +
                " per multiplication)");
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   world = MPI_COMM_WORLD;
  check_exact_sum(world);
  for (const bool chunks : {false, true})
    {
      check_solvers(world, false, chunks);
      check_solvers(world, true, chunks);
    }
  const int failures = Utilities::MPI::max(n_failures, world);
  if (Utilities::MPI::this_mpi_process(world) == 0)
    std::cout << (failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return failures;
}
