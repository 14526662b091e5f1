// The FETI operators on distributed dual vectors (DualSpace): on P ranks, each owning a
// contiguous range of the 12 subdomains of the brick (TFETI, 3 × 2 × 2 blocks), F x, the lumped
// preconditioner, G x, Gᵀy, the projector P, the least-norm and the tiered particular solution of
// Gλ = e, the primal recovery and B u − c must be the same bits as on one rank holding everything
// (a DualProblem on MPI_COMM_SELF), and so must the dot products of the distributed vectors,
// while a rank holds fewer entries of G (those of its relevant columns) than one rank holding
// everything. With the rows of B made per
// rank (build_local_equality_rows: each rank the rows that touch its subdomains), the rows are
// those of one rank holding all, and F x, h, c and the primal recovery the same bits; so are F x
// and h with contact-like rows before them, each held together with an empty row that rank 0
// adds up (DualRows::rows_touching).

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/equality_constraints.h>

#include "test_tools.h"

#include <cstring>
#include <random>

using namespace dealii;
using namespace FetiContact;

namespace
{
  /** Whether @p a and @p b hold the same bits. */
  bool
  same_bits(const Vector<double> &a, const Vector<double> &b)
  {
    return a.size() == b.size() &&
           std::memcmp(a.begin(), b.begin(), a.size() * sizeof(double)) == 0;
  }

  bool
  same_bits(const double a, const double b)
  {
    return std::memcmp(&a, &b, sizeof(double)) == 0;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   world   = MPI_COMM_WORLD;
  const unsigned int               n_ranks = Utilities::MPI::n_mpi_processes(world);
  const unsigned int               rank    = Utilities::MPI::this_mpi_process(world);
  const FESystem<3>                fe(FE_SimplexP<3>(1), 3);
  const MappingFE<3>               mapping(FE_SimplexP<3>(1));

  const auto scene = scene_from_text(brick_text("set Method = blocks\nset Blocks = 3, 2, 2"));
  std::vector<std::unique_ptr<Body>> bodies;
  bodies.push_back(std::make_unique<Body>(scene.bodies[0], 0));
  bodies[0]->setup();
  const unsigned int n_sub = bodies[0]->partition.n_parts;

  // Every subdomain on every rank (for the reference); this rank's contiguous range.
  std::vector<std::unique_ptr<Subdomain>> subdomains;
  std::vector<Subdomain *>                all, own;
  std::vector<unsigned int>               mode_offset{0};
  const unsigned int first = n_sub * rank / n_ranks, last = n_sub * (rank + 1) / n_ranks;
  for (unsigned int p = 0; p < n_sub; ++p)
    {
      subdomains.push_back(
        std::make_unique<Subdomain>(*bodies[0], bodies[0]->part_cells(p), p, false, fe));
      subdomains.back()->assemble(mapping);
      subdomains.back()->factorize("cholmod");
      all.push_back(subdomains.back().get());
      if (p >= first && p < last)
        own.push_back(subdomains.back().get());
      mode_offset.push_back(mode_offset.back() + subdomains.back()->R.n());
    }
  // The rows that the ranks make for their own subdomains and gather are those of one rank
  // holding every subdomain, in the same order.
  const DualRows rows      = build_equality_rows(MPI_COMM_SELF, all, true);
  const DualRows gathered  = build_equality_rows(world, own, true);
  bool           same_rows = rows.row_start == gathered.row_start && rows.c == gathered.c;
  for (unsigned int k = 0; same_rows && k < rows.entries.size(); ++k)
    same_rows = rows.entries[k].subdomain == gathered.entries[k].subdomain &&
                rows.entries[k].body_vertex == gathered.entries[k].body_vertex &&
                rows.entries[k].component == gathered.entries[k].component &&
                rows.entries[k].value == gathered.entries[k].value;
  check(same_rows,
        "the rows of B_E gathered from the ranks' subdomains are those of one rank holding all");
  const DualProblem reference(MPI_COMM_SELF, all, mode_offset, rows);
  const DualProblem dual(world, own, mode_offset, rows);
  const auto       &d  = dual.space();
  const std::string on = " on " + std::to_string(n_ranks) + " rank(s) (" +
                         std::to_string(d.partitioner()->ghost_targets().size()) + " neighbours, " +
                         std::to_string(d.partitioner()->n_ghost_indices()) +
                         " ghost values received)";

  const unsigned int                     m = reference.size();
  std::mt19937                           random(5);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Vector<double>                         x(m), y(reference.coarse.n_modes());
  for (auto &xi : x)
    xi = uniform(random);
  for (auto &yi : y)
    yi = uniform(random);
  const DualVector x_d = d.restrict(x);
  // The reference's products on vectors of all rows.
  const auto &rd          = reference.space();
  const auto  on_all_rows = [&](const DualProblem &problem, const auto &product) {
    return [&problem, product](const Vector<double> &v, Vector<double> &w) {
      DualVector result;
      (problem.*product)(problem.space().restrict(v), result);
      w = problem.space().gather(result);
    };
  };
  const auto reference_F      = on_all_rows(reference, &DualProblem::apply_F);
  const auto reference_lumped = on_all_rows(reference, &DualProblem::apply_lumped);

  Vector<double> Fx, lumped_x;
  DualVector     Fx_d, lumped_x_d;
  reference_F(x, Fx);
  dual.apply_F(x_d, Fx_d);
  check(same_bits(d.gather(Fx_d), Fx), "F x" + on + ": the same bits as on one rank");
  reference_lumped(x, lumped_x);
  dual.apply_lumped(x_d, lumped_x_d);
  check(same_bits(d.gather(lumped_x_d), lumped_x),
        "lumped preconditioner" + on + ": the same bits as on one rank");

  Vector<double> Gx, Gx_d, Gty;
  reference.coarse.apply_G(rd.restrict(x), Gx);
  dual.coarse.apply_G(x_d, Gx_d);
  DualVector Gty_d, Gty_one;
  reference.coarse.apply_Gt(y, Gty_one);
  Gty = rd.gather(Gty_one);
  dual.coarse.apply_Gt(y, Gty_d);
  check(same_bits(Gx, Gx_d) && same_bits(d.gather(Gty_d), Gty),
        "G x and Gᵀy" + on + ": the same bits as on one rank");

  DualVector Px_one = rd.restrict(x), lambda0_one;
  reference.coarse.project(Px_one);
  reference.coarse.least_norm_solution(reference.e, lambda0_one);
  const Vector<double> Px = rd.gather(Px_one), lambda0 = rd.gather(lambda0_one);
  DualVector           Px_d(x_d), lambda0_d;
  dual.coarse.project(Px_d);
  dual.coarse.least_norm_solution(dual.e, lambda0_d);
  check(same_bits(d.gather(Px_d), Px) && same_bits(d.gather(lambda0_d), lambda0),
        "P x and the least-norm solution of Gλ = e" + on + ": the same bits as on one rank");

  const auto u_reference = reference.recover_primal(lambda0_one);
  const auto u           = dual.recover_primal(lambda0_d);
  bool       same_u      = u.size() == own.size();
  for (unsigned int i = 0; same_u && i < own.size(); ++i)
    same_u = same_bits(u[i], u_reference[first + i]);
  const Vector<double> r_reference = rd.gather(reference.constraint_residual(u_reference));
  const Vector<double> r           = d.gather(dual.constraint_residual(u));
  check(same_u && same_bits(r, r_reference),
        "primal recovery and B u − c" + on + ": the same bits as on one rank");

  const DualVector x_one  = rd.restrict(x);
  const DualVector Fx_one = rd.restrict(Fx);
  using namespace ReproducibleReductions;
  check(same_bits(dot(x_d, Fx_d), dot(x_one, Fx_one)) && same_bits(l2_norm(Fx_d), l2_norm(Fx_one)),
        "xᵀF x and ‖F x‖" + on + ": the same bits as on one rank (" + sci(dot(x_d, Fx_d)) + ")");

  const auto tier = [](const unsigned int c) { return c % 10 == 0 ? 1u : 0u; };
  DualVector tiered_d, tiered_one;
  dual.coarse.particular_solution(dual.e, tier, tiered_d);
  reference.coarse.particular_solution(reference.e, tier, tiered_one);
  check(same_bits(d.gather(tiered_d), rd.gather(tiered_one)),
        "the tiered particular solution of Gλ = e" + on + ": the same bits as on one rank");
  check(n_ranks == 1 ||
          Utilities::MPI::max(dual.coarse.n_entries(), world) < reference.coarse.n_entries(),
        "G by columns" + on + ": at most " +
          std::to_string(Utilities::MPI::max(dual.coarse.n_entries(), world)) + " of the " +
          std::to_string(reference.coarse.n_entries()) + " entries of G on a rank");

  // Rows held per rank: the rows of this rank's subdomains, made and numbered without a rank
  // holding all, are those of one rank holding all, and the dual problem on them gives the same
  // bits.
  std::vector<unsigned int> owner(n_sub);
  for (unsigned int q = 0; q < n_ranks; ++q)
    for (unsigned int p = n_sub * q / n_ranks; p < n_sub * (q + 1) / n_ranks; ++p)
      owner[p] = q;
  const DualRows local = build_local_equality_rows(world, own, owner, true);
  const DualRows touching =
    rows.rows_touching([&](const unsigned int s) { return owner[s] == rank; }, false);
  bool same_local = local.n_all == rows.n_all && local.number == touching.number &&
                    local.row_start == touching.row_start && local.c == touching.c &&
                    local.entries.size() == touching.entries.size();
  for (unsigned int k = 0; same_local && k < local.entries.size(); ++k)
    same_local = local.entries[k].subdomain == touching.entries[k].subdomain &&
                 local.entries[k].body_vertex == touching.entries[k].body_vertex &&
                 local.entries[k].component == touching.entries[k].component &&
                 local.entries[k].value == touching.entries[k].value;
  check(Utilities::MPI::min(same_local ? 1u : 0u, world) == 1,
        "the rows of B_E made per rank are those of one rank holding all that touch its "
        "subdomains, with the same numbers");
  check(n_ranks == 1 || Utilities::MPI::max(local.n_rows(), world) < rows.n_rows(),
        "rows per rank: at most " + std::to_string(Utilities::MPI::max(local.n_rows(), world)) +
          " of the " + std::to_string(rows.n_rows()) + " rows on a rank");
  const DualProblem on_local(world, own, mode_offset, local);
  const auto       &d_l = on_local.space();
  DualVector        Fx_l, lumped_x_l, lambda0_l;
  on_local.apply_F(d_l.restrict(x), Fx_l);
  on_local.apply_lumped(d_l.restrict(x), lumped_x_l);
  on_local.coarse.least_norm_solution(on_local.e, lambda0_l);
  const auto u_l      = on_local.recover_primal(lambda0_l);
  bool       same_u_l = u_l.size() == own.size();
  for (unsigned int i = 0; same_u_l && i < own.size(); ++i)
    same_u_l = same_bits(u_l[i], u_reference[first + i]);
  check(on_local.size() == m && same_bits(d_l.gather(Fx_l), Fx) &&
          same_bits(d_l.gather(lumped_x_l), lumped_x) &&
          same_bits(d_l.gather(on_local.h), rd.gather(reference.h)) &&
          same_bits(d_l.gather(on_local.c), rd.gather(reference.c)) &&
          same_bits(d_l.gather(lambda0_l), lambda0) && same_u_l &&
          same_bits(d_l.gather(on_local.constraint_residual(u_l)), r_reference),
        "rows per rank" + on +
          ": F x, the lumped preconditioner, h, c, λ₀, the primal recovery and B u − c the same "
          "bits as on one rank");

  // Contact-like rows before the equality rows: every fifth row of B_E as a "normal" row held
  // together with an empty "tangential" row (rank 0 adds it up), as the rows of a roller node.
  DualRows contact;
  for (unsigned int r = 0; r < rows.n_rows(); r += 5)
    {
      contact.held_together.push_back({contact.n_rows(), contact.n_rows() + 1});
      contact.held_by.push_back(numbers::invalid_unsigned_int);
      contact.add_row_of(rows, r, contact.n_all++);
      contact.add_row({}, 0.0);
    }
  DualRows all_rows = contact,
           own_rows = contact.rows_touching([&](const unsigned int s) { return owner[s] == rank; },
                                            rank == 0);
  all_rows.append(rows);
  own_rows.append(local);
  const DualProblem with_contact(MPI_COMM_SELF, all, mode_offset, all_rows);
  const DualProblem own_contact(world, own, mode_offset, own_rows);
  const auto       &d_c = own_contact.space();
  Vector<double>    x_c(all_rows.n_rows()), Fx_c;
  for (auto &xi : x_c)
    xi = uniform(random);
  DualVector Fx_own;
  on_all_rows(with_contact, &DualProblem::apply_F)(x_c, Fx_c);
  own_contact.apply_F(d_c.restrict(x_c), Fx_own);
  check(own_rows.n_all == all_rows.n_rows() && same_bits(d_c.gather(Fx_own), Fx_c) &&
          same_bits(d_c.gather(own_contact.h), with_contact.space().gather(with_contact.h)),
        "rows per rank with empty rows held together before them" + on +
          ": F x and h the same bits as on one rank");

  const int failures = Utilities::MPI::max(n_failures, world);
  if (rank == 0)
    std::cout << (failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return failures;
}
