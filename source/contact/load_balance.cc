#include <deal.II/base/mpi.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/load_balance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * The columns of W of one contact node: the work of a unit force along n, t1, t2 on the
     * free motions of the (at most two) floating bodies it touches, −v_j(x) on the slave and
     * +v_j(χ(x)) on the master.
     */
    struct NodeColumns
    {
      struct Side
      {
        unsigned int           offset = 0, count = 0;
        std::array<double, 18> work{}; ///< [3 j + c]
      };
      std::array<Side, 2> sides;
      double              friction = 0;
      double              g        = -1; ///< Tresca: the slip bound; Coulomb: −1
      /**
       * A node whose friction acts through its vertex's keeper (ContactNode::keeper): its
       * tangential columns are the keeper's directions with its own cone (Coulomb: the cones
       * add up, as the slip bounds do); with Tresca's law the vertex has the keeper's bound
       * alone (the companions' columns get 0), as in the solver.
       */
      bool has_keeper = false;
    };

    /**
     * The test's data: W by node, e, and the admissible set of every node. The nodes are this
     * rank's, and the sums over them (W p, dot products, the certificate's sum) are over the
     * nodes of all ranks of comm: per chunk (the nodes of one home subdomain, all on one rank)
     * in the order of the nodes, the chunks' sums exactly (ExactSum), so that every sum is the
     * same bits on any number of ranks.
     */
    struct BalanceProblem
    {
      std::vector<NodeColumns>      columns;
      std::vector<unsigned int>     node_of_column;  ///< the contact node of every column
      std::vector<unsigned int>     chunk_of_column; ///< its chunk, numbered on this rank
      unsigned int                  n_chunks = 0;
      unsigned int                  n_nodes  = 0; ///< this rank's contact nodes, floating or not
      Vector<double>                e;
      std::vector<FreeRigidMotions> motions; ///< by body
      std::vector<unsigned int>     offset;  ///< of each body's motions in e
      std::vector<std::string>      names;   ///< by body
      MPI_Comm                      comm = MPI_COMM_SELF;

      unsigned int
      n_unknowns() const
      {
        return 3 * columns.size();
      }

      /**
       * Σ_k term(k, sums) over the columns of all ranks, per entry of the result (@p n
       * entries): @p term adds column k's terms to the chunk's partial sums.
       */
      template <typename Term>
      std::vector<double>
      sum_over_columns(const unsigned int n, const Term &term) const
      {
        std::vector<double> partial(n_chunks * n, 0.);
        for (unsigned int k = 0; k < columns.size(); ++k)
          term(k, &partial[n * chunk_of_column[k]]);
        std::vector<ExactSum> sum(n);
        for (unsigned int c = 0; c < n_chunks; ++c)
          for (unsigned int i = 0; i < n; ++i)
            sum[i].add(partial[n * c + i]);
        ExactSum::sum_over_ranks(sum, comm);
        std::vector<double> total(n);
        for (unsigned int i = 0; i < n; ++i)
          total[i] = sum[i].value();
        return total;
      }

      /** (xᵀy, yᵀy) over the unknowns of all ranks, in one reduction. */
      std::array<double, 2>
      dots(const Vector<double> &x, const Vector<double> &y) const
      {
        const std::vector<double> s = sum_over_columns(2, [&](const unsigned int k, double *s) {
          for (unsigned int c = 0; c < 3; ++c)
            {
              s[0] += x[3 * k + c] * y[3 * k + c];
              s[1] += y[3 * k + c] * y[3 * k + c];
            }
        });
        return {{s[0], s[1]}};
      }

      /** r = W p. */
      void
      apply_W(const Vector<double> &p, Vector<double> &r) const
      {
        const std::vector<double> total =
          sum_over_columns(r.size(), [&](const unsigned int k, double *s) {
            for (const auto &side : columns[k].sides)
              for (unsigned int j = 0; j < side.count; ++j)
                for (unsigned int c = 0; c < 3; ++c)
                  s[side.offset + j] += side.work[3 * j + c] * p[3 * k + c];
          });
        std::copy(total.begin(), total.end(), r.begin());
      }

      /** y = Wᵀ α. */
      void
      apply_Wt(const Vector<double> &alpha, Vector<double> &y) const
      {
        y = 0;
        for (unsigned int k = 0; k < columns.size(); ++k)
          for (const auto &side : columns[k].sides)
            for (unsigned int j = 0; j < side.count; ++j)
              for (unsigned int c = 0; c < 3; ++c)
                y[3 * k + c] += side.work[3 * j + c] * alpha[side.offset + j];
      }

      /** The projection of (p_N, p_T) of node @p k on its set (a cone, or a bound × a disc). */
      void
      project(const unsigned int k, double *p) const
      {
        const auto  &node = columns[k];
        const double t    = std::hypot(p[1], p[2]);
        if (node.g >= 0)
          {
            p[0] = std::max(p[0], 0.0);
            if (t > node.g)
              for (unsigned int c = 1; c < 3; ++c)
                p[c] *= node.g / t;
            return;
          }
        const double F = node.friction;
        if (t <= F * p[0])
          return;
        if (F * t <= -p[0])
          {
            p[0] = p[1] = p[2] = 0;
            return;
          }
        const double normal = (p[0] + F * t) / (1 + F * F);
        p[0]                = normal;
        for (unsigned int c = 1; c < 3; ++c)
          p[c] *= F * normal / t;
      }

      void
      project(Vector<double> &p) const
      {
        for (unsigned int k = 0; k < columns.size(); ++k)
          project(k, &p[3 * k]);
      }

      /**
       * The certificate test of α: the largest total magnitude of admissible contact forces
       * that cannot do the work αᵀe on α (infinite if none can: an exact proof), or 0 if α is
       * no certificate.
       */
      double
      force_bound(const Vector<double> &alpha, Vector<double> &y) const
      {
        apply_Wt(alpha, y);
        double s_max = 0;
        for (unsigned int k = 0; k < columns.size(); ++k)
          {
            const double *yk = &y[3 * k];
            if (columns[k].g >= 0)
              s_max = std::max(s_max, std::max(yk[0], 0.0));
            else
              {
                std::array<double, 3> projected{{yk[0], yk[1], yk[2]}};
                project(k, projected.data());
                s_max =
                  std::max(s_max,
                           std::sqrt(projected[0] * projected[0] + projected[1] * projected[1] +
                                     projected[2] * projected[2]));
              }
          }
        s_max               = Utilities::MPI::max(s_max, comm);
        const double c_sum  = sum_over_columns(1, [&](const unsigned int k, double *s) {
          if (columns[k].g >= 0)
            s[0] += columns[k].g * std::hypot(y[3 * k + 1], y[3 * k + 2]);
        })[0];
        const double margin = alpha * e - c_sum;
        if (margin <= 0)
          return 0;
        return s_max > 0 ? margin / s_max : std::numeric_limits<double>::infinity();
      }
    };

    BalanceProblem
    build_problem(const std::vector<std::unique_ptr<Body>> &bodies,
                  const std::vector<ContactNode>           &nodes,
                  const MPI_Comm                            comm)
    {
      BalanceProblem problem;
      problem.comm = comm;
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> chunk; // (body, home part)
      unsigned int                                                  n_motions = 0;
      for (const auto &body : bodies)
        {
          problem.motions.push_back(body->free_rigid_motions());
          problem.offset.push_back(n_motions);
          problem.names.push_back(body->parameters.name);
          n_motions += problem.motions.back().n();
        }
      problem.e.reinit(n_motions);
      for (unsigned int b = 0; b < bodies.size(); ++b)
        {
          const Vector<double> w = bodies[b]->load_work(problem.motions[b]);
          for (unsigned int j = 0; j < w.size(); ++j)
            problem.e[problem.offset[b] + j] = -w[j];
        }
      problem.n_nodes = nodes.size();
      for (unsigned int k = 0; k < nodes.size(); ++k)
        {
          const ContactNode &node = nodes[k];
          NodeColumns        columns;
          columns.friction            = node.friction;
          columns.has_keeper          = node.keeper.has_value();
          const ContactNode &tangents = node.keeper ? nodes[*node.keeper] : node;
          const std::array<const Tensor<1, 3> *, 3> frame{{&node.n, &tangents.t1, &tangents.t2}};
          const auto                                add_side = [&](NodeColumns::Side &side,
                                    const unsigned int body,
                                    const Point<3>    &x,
                                    const double       sign) {
            const auto &motions = problem.motions[body];
            side.offset         = problem.offset[body];
            side.count          = motions.n();
            for (unsigned int j = 0; j < motions.n(); ++j)
              {
                const Tensor<1, 3> v = motions.value(j, x);
                for (unsigned int c = 0; c < 3; ++c)
                  side.work[3 * j + c] = sign * (*frame[c] * v);
              }
          };
          add_side(columns.sides[0], node.body, node.x, -1.0);
          // The weights sum to 1 and a rigid motion is affine: its value at the weighted mean
          // of the master vertices is the weighted mean of its values there.
          if (node.on_body())
            add_side(columns.sides[1], node.master.front().body, master_point(node), 1.0);
          if (columns.sides[0].count + columns.sides[1].count > 0)
            {
              problem.columns.push_back(columns);
              problem.node_of_column.push_back(k);
              const auto home =
                chunk.emplace(std::make_pair(node.body, node.copies.parts.front()), chunk.size());
              problem.chunk_of_column.push_back(home.first->second);
            }
        }
      problem.n_chunks = chunk.size();
      return problem;
    }

    /** An upper estimate of ‖W‖² (power iteration on W Wᵀ, with a margin). */
    double
    norm_squared(const BalanceProblem &problem)
    {
      Vector<double> alpha(problem.e.size()), y(problem.n_unknowns()), r(problem.e.size());
      for (unsigned int i = 0; i < alpha.size(); ++i)
        alpha[i] = 1.0 + 0.1 * i;
      double estimate = 0;
      for (unsigned int it = 0; it < 30; ++it)
        {
          alpha /= alpha.l2_norm();
          problem.apply_Wt(alpha, y);
          problem.apply_W(y, r);
          estimate = r.l2_norm();
          if (estimate == 0)
            return 1;
          alpha = r;
        }
      return 1.1 * estimate;
    }

    /** The motion β = −α of the certificate, body by body, for the message. */
    std::string
    motion_text(const BalanceProblem &problem, const Vector<double> &alpha)
    {
      std::ostringstream text;
      bool               first = true;
      for (unsigned int b = 0; b < problem.motions.size(); ++b)
        {
          const auto  &motions = problem.motions[b];
          Tensor<1, 3> translation, rotation;
          for (unsigned int j = 0; j < motions.n(); ++j)
            for (unsigned int i = 0; i < 3; ++i)
              {
                translation[i] -= motions.coefficients(i, j) * alpha[problem.offset[b] + j];
                rotation[i] -= motions.coefficients(i + 3, j) * alpha[problem.offset[b] + j];
              }
          if (translation.norm() + rotation.norm() < 1e-3)
            continue;
          const auto vector_text = [](const Tensor<1, 3> &v) {
            const auto number = [](const double x) {
              return InputParsing::number_text(std::abs(x) < 5e-4 ? 0.0 :
                                                                    std::round(x * 1e3) / 1e3);
            };
            return '(' + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + ')';
          };
          text << (first ? "" : "; ") << "body '" << problem.names[b] << "' moving by "
               << vector_text(translation);
          if (rotation.norm() >= 1e-3)
            text << " and turning by " << vector_text(rotation)
                 << "/L (L = " << InputParsing::number_text(motions.length) << ", its size)";
          first = false;
        }
      return text.str();
    }
  } // namespace

  struct LoadBalanceTest::Problem : BalanceProblem
  {};

  LoadBalanceTest::LoadBalanceTest(const std::vector<std::unique_ptr<Body>> &bodies,
                                   const std::vector<ContactNode>           &nodes,
                                   const MPI_Comm                            comm)
    : problem(std::make_unique<Problem>())
  {
    static_cast<BalanceProblem &>(*problem) = build_problem(bodies, nodes, comm);
  }

  LoadBalanceTest::~LoadBalanceTest() = default;

  bool
  LoadBalanceTest::has_free_motions() const
  {
    return problem->e.size() > 0 && problem->e.l2_norm() > 0;
  }

  LoadBalance
  LoadBalanceTest::coulomb(const unsigned int max_iterations)
  {
    return tresca(std::vector<double>(), max_iterations);
  }

  LoadBalance
  LoadBalanceTest::tresca(const std::vector<double> &slip_bounds, const unsigned int max_iterations)
  {
    AssertThrow(slip_bounds.empty() || slip_bounds.size() == problem->n_nodes,
                ExcDimensionMismatch(slip_bounds.size(), problem->n_nodes));
    for (unsigned int k = 0; k < problem->columns.size(); ++k)
      problem->columns[k].g = slip_bounds.empty() ? -1 :
                              problem->columns[k].friction > 0 && !problem->columns[k].has_keeper ?
                                                    slip_bounds[problem->node_of_column[k]] :
                                                    0;
    const BalanceProblem &problem = *this->problem;
    LoadBalance           result;
    result.load_resultant = problem.e.l2_norm();
    if (problem.e.size() == 0 || result.load_resultant == 0)
      return result; // nothing floats, or nothing loads the floating bodies

    const unsigned int n = problem.n_unknowns();
    Vector<double>     p(n), z(n), p_new(n), gradient(n), y(n);
    Vector<double>     r(problem.e.size()), r_new(problem.e.size()), alpha(problem.e.size());
    double             L = norm_squared(problem), t = 1;
    const double       enough = 1e4 * result.load_resultant;

    const auto residual = [&](const Vector<double> &x, Vector<double> &res) {
      problem.apply_W(x, res);
      res -= problem.e;
      return 0.5 * (res * res);
    };
    const auto certificate = [&](const Vector<double> &res) {
      alpha = res;
      alpha *= -1.0 / res.l2_norm();
      const double bound = problem.force_bound(alpha, y);
      if (bound >= enough)
        {
          result.outcome     = LoadBalance::Outcome::impossible;
          result.load_work   = alpha * problem.e;
          result.force_bound = bound;
          result.motion      = motion_text(problem, alpha);
          return true;
        }
      return false;
    };

    double f_p = residual(p, r);
    if (certificate(r))
      return result;
    result.outcome = LoadBalance::Outcome::undecided;
    for (unsigned int it = 1; it <= max_iterations; ++it)
      {
        result.iterations = it;
        // FISTA step from z with backtracking on L.
        const double f_z = residual(z, r);
        problem.apply_Wt(r, gradient);
        double f_new = 0;
        for (unsigned int attempt = 0; attempt < 60; ++attempt)
          {
            p_new = z;
            p_new.add(-1.0 / L, gradient);
            problem.project(p_new);
            Vector<double> d(p_new);
            d -= z;
            f_new                 = residual(p_new, r_new);
            const auto [g_d, d_d] = problem.dots(gradient, d);
            if (f_new <= f_z + g_d + 0.5 * L * d_d * (1 + 1e-12))
              break;
            L *= 2;
          }
        if (f_new > f_p) // restart the momentum
          {
            t = 1;
            z = p;
            continue;
          }
        const double t_new = 0.5 * (1 + std::sqrt(1 + 4 * t * t));
        z                  = p_new;
        z.sadd(1 + (t - 1) / t_new, -(t - 1) / t_new, p);
        t                        = t_new;
        p                        = p_new;
        f_p                      = f_new;
        result.relative_residual = std::sqrt(2 * f_p) / result.load_resultant;
        if (result.relative_residual <= 1e-6)
          {
            result.outcome = LoadBalance::Outcome::balanced;
            return result;
          }
        if (it % 10 == 0 && certificate(r_new))
          return result;
      }
    return result;
  }

  LoadBalance
  test_load_balance(const std::vector<std::unique_ptr<Body>> &bodies,
                    const std::vector<ContactNode>           &nodes,
                    const double                              tresca_slip_bound,
                    const unsigned int                        max_iterations)
  {
    LoadBalanceTest test(bodies, nodes, MPI_COMM_SELF);
    if (tresca_slip_bound < 0)
      return test.coulomb(max_iterations);
    return test.tresca(std::vector<double>(nodes.size(), tresca_slip_bound), max_iterations);
  }
} // namespace FetiContact
