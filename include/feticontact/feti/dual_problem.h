#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_space.h>
#include <feticontact/feti/equality_constraints.h>
#include <feticontact/subdomain/subdomain.h>

#include <memory>
#include <mpi.h>
#include <utility>
#include <vector>

namespace FetiContact
{
  /**
   * B_i of one subdomain in coordinate form: rows (their numbers), DoFs of subdomain i, values,
   * and the slot of each entry (its local index in the vector of the slots, the nonzeros of B,
   * where B_i u_i is written).
   */
  struct BlockOfB
  {
    std::vector<unsigned int> row, dof, slot;
    std::vector<double>       value;
  };

  /**
   * The FETI dual problem
   *
   *   min ½ λᵀFλ − λᵀh  s.t.  Gλ = e  (and, with contact, bounds on some components of λ)
   *
   * with F = B K⁺ Bᵀ, h = B K⁺ f − c, G = Rᵀ Bᵀ, e = Rᵀ f, assembled from the blocks B_i of the
   * subdomains that this rank owns. The dual vectors are deal.II's distributed vectors on the
   * partitioner of space(): every row belongs to the rank of the first subdomain in its
   * summation order, or of the subdomain its set of rows held together names (DualRows::held_by;
   * the contact rows of a slave vertex, its home subdomain), and the rows that touch a rank's
   * subdomains are its ghosts. F is applied subdomain by subdomain, and the sum is
   * rank-independent: every subdomain writes its terms B_i u_i into its own slots (the entries of
   * a distributed vector with one entry per nonzero of B, owned by the row's rank), the slots of
   * other ranks' subdomains reach the row's rank unchanged (compress(add) onto zero), and every
   * row adds its slots in the order of increasing subdomain. F x, h and B u − c are then the same
   * bits on any number of ranks and any assignment of subdomains to ranks, and so are the iterates
   * and iteration counts of the solvers that use them (floating-point addition is not associative:
   * a sum in rank order made n_A differ by 8 % between one and two ranks). Knows nothing of
   * friction: it sees rows of B and their right-hand side c.
   */
  class DualProblem
  {
  public:
    /**
     * @p owned: this rank's subdomains (factorized); @p mode_offset: first rigid mode of every
     * global subdomain (size n_subdomains + 1); @p rows: at least the rows that touch this rank's
     * subdomains, with c (DualRows::rows_touching(), build_local_equality_rows()): a rank holds
     * nothing of the length of all rows but what the coarse problem needs. @p coarse_factor:
     * where the factor of GGᵀ is kept (CoarseProblem::FactorStorage).
     */
    DualProblem(
      const MPI_Comm                     comm,
      const std::vector<Subdomain *>    &owned,
      const std::vector<unsigned int>   &mode_offset,
      const DualRows                    &rows,
      const CoarseProblem::FactorStorage coarse_factor = CoarseProblem::FactorStorage::per_node);

    /** The number of dual unknowns m. */
    unsigned int
    size() const
    {
      return n_all_rows;
    }

    /** y = F x (counted in n_F_applications, timed in F_time). */
    void
    apply_F(const DualVector &x, DualVector &y) const;

    /**
     * The dual space: the rows this rank adds up (those of its first subdomain in summation
     * order) and, as ghosts, the other rows of its subdomains.
     */
    const DualSpace &
    space() const
    {
      return *dual_space;
    }

    /** What one application of F exchanges on this rank, counted in values (doubles). */
    struct CommunicationVolume
    {
      /** Ranks this rank exchanges slots with (terms B_i u_i of rows another rank adds up). */
      unsigned int slot_neighbours = 0;
      /** Slot values sent and received (point to point). */
      std::size_t slots_sent = 0, slots_received = 0;
      /** Ranks the ghost rows come from, and their number. */
      unsigned int ghost_neighbours = 0;
      std::size_t  ghosts_received  = 0;
    };

    /** This rank's exchanges in one application of F (from the setup; no communication). */
    CommunicationVolume
    communication_volume() const;

    /**
     * y = D B K Bᵀ D x, the lumped FETI preconditioner (Farhat–Mandel–Roux) with the row scaling
     * D = diag(B Bᵀ)⁻¹: a gluing row between two subdomains (entries ±1) counts ½, a Dirichlet
     * or contact row with a unit normal 1. An approximation of F⁻¹ at the cost of one sparse
     * multiplication by K_i per subdomain, no solve (counted in n_lumped_applications, timed in
     * lumped_time).
     */
    void
    apply_lumped(const DualVector &x, DualVector &y) const;

    /**
     * The primal solution u_i = K_i⁺(f_i − B_iᵀλ) + R_i α_i of every owned subdomain, with
     * α = (GGᵀ)⁻¹G(Fλ − h) (so that B u = c holds in the least-squares sense on the range of G).
     */
    std::vector<dealii::Vector<double>>
    recover_primal(const DualVector &lambda) const;

    /** The same with given coefficients α of the rigid modes (e.g. from SMALBE's multiplier). */
    std::vector<dealii::Vector<double>>
    recover_primal(const DualVector &lambda, const dealii::Vector<double> &alpha) const;

    /** r = B u − c on this rank's rows, from the subdomain solutions of this rank. */
    DualVector
    constraint_residual(const std::vector<dealii::Vector<double>> &u) const;

    CoarseProblem coarse;
    /** h and c on this rank's rows (vectors of space()). */
    DualVector h, c;
    /** e = Rᵀf, on every rank. */
    dealii::Vector<double> e;
    mutable unsigned int   n_F_applications = 0;
    /** Wall time spent in apply_F (local solves, B and Bᵀ, the sum over ranks) [s]. */
    mutable double F_time = 0;
    /**
     * The part of F_time spent in this rank's own subdomains (Bᵀ, the local solves, B): the
     * rest is the exchange of the slots, the row sums of this rank's block, and waiting for the
     * other ranks.
     */
    mutable double F_local_time = 0;
    /** The subdomain solves this rank made in apply_F. */
    mutable unsigned long n_subdomain_solves    = 0;
    mutable unsigned int  n_lumped_applications = 0;
    /** Wall time spent in apply_lumped [s]. */
    mutable double lumped_time = 0;

  private:
    /** Writes the terms of B_i u into the slots of subdomain i. */
    void
    set_B_slots(const unsigned int i, const dealii::Vector<double> &u) const;
    /**
     * The rank of every subdomain, and of every row given (the rank that adds it up) with its
     * first subdomain in summation order (its chunk of the dual vectors' sums).
     */
    struct Owners
    {
      std::vector<int>          subdomain_rank, row_rank;
      std::vector<unsigned int> first_subdomain;

      /** The rank of the subdomain of entry @p k of @p rows. */
      int
      rank_of_entry(const DualRows &rows, const unsigned int k) const;
    };
    /**
     * The dual space and the slots (from the rows and the owners). Owners::row_rank is given
     * for the rows of @p rows.
     */
    Owners
    setup_row_sums(const DualRows &rows, const unsigned int n_subdomains);
    /** The owners of the subdomains and of the rows given (collective). */
    Owners
    row_owners(const DualRows &rows, const unsigned int n_subdomains) const;
    /** The dual space and the local index of the row of every entry of B_i. */
    void
    set_up_space(const DualRows &rows, const Owners &owners);
    /** The vector of the slots and the local slot of every entry of B_i. */
    void
    set_up_slots(const DualRows &rows, const Owners &owners);
    /** The index in @p rows of the row numbered @p number. */
    static unsigned int
    index_of_row(const DualRows &rows, const unsigned int number);
    /** c and h on this rank's rows (from the slots of B K⁺f). */
    void
    set_up_right_hand_sides(const DualRows &rows);
    /**
     * The entries of G in the columns relevant to this rank, from @p own_entries (those of its
     * modes) of every rank (point to point).
     */
    std::vector<CoarseProblem::Entry>
    relevant_G_entries(const std::vector<CoarseProblem::Entry> &own_entries,
                       const DualRows                          &rows,
                       const Owners                            &owners) const;
    /** x = B_iᵀ λ, with the ghosts of λ up to date. */
    void
    set_Bt(const unsigned int i, const DualVector &lambda, dealii::Vector<double> &x) const;
    /**
     * Brings the slots of other ranks' subdomains in this rank's rows here, and sends this rank's
     * slots in other ranks' rows.
     */
    void
    exchange_slots() const;
    /** The sums of this rank's rows (after exchange_slots()), in the order of the owned entries. */
    void
    sum_own_rows(double *sums) const;
    /** y = the row sums of the slots written (exchange_slots(), then sum_own_rows()). */
    void
    sum_rows_into(DualVector &y) const;
    /** B_i of every owned subdomain from the rows (DoFs looked up by body vertex). */
    void
    build_blocks(const DualRows &rows);
    /**
     * The range of the rigid modes of this rank's subdomains, for G x on distributed vectors
     * (CoarseProblem::distribute): they follow each other in rank order.
     */
    std::pair<unsigned int, unsigned int>
    own_modes(const std::vector<unsigned int> &mode_offset) const;

    /** The rows of this rank's dual vectors, and the other rows of its subdomains. */
    std::unique_ptr<DualSpace> dual_space;
    /** Per owned subdomain: the local index in the dual vectors of the row of every entry of B_i.
     */
    std::vector<std::vector<unsigned int>> row_local;
    /** D of apply_lumped, with its ghosts. */
    mutable DualVector lumped_scale;
    /** D x in apply_lumped, with its ghosts. */
    mutable DualVector x_scaled;

    /** Work vectors of apply_lumped: K_i Bᵀ D x per owned subdomain. */
    mutable std::vector<dealii::Vector<double>> lumped_Ku;

    MPI_Comm                 comm;
    std::vector<Subdomain *> owned;
    /** The number of all rows (m). */
    unsigned int                                n_all_rows = 0;
    std::vector<BlockOfB>                       B;
    std::vector<unsigned int>                   first_mode;
    mutable std::vector<dealii::Vector<double>> work;
    /** The entries of every row given in summation order (CSR: slot_start, slot_order). */
    std::vector<unsigned int> slot_start, slot_order;
    /**
     * One number per nonzero of B: B_i u_i entry by entry, numbered by the rows' order in the
     * dual vectors and within a row in its summation order. A rank owns the slots of its rows;
     * its blocks write their slots (owned or ghost) in every product, and the owned slots of
     * other ranks' subdomains (foreign_slots) are set to zero before the ghosts are added to
     * them.
     */
    mutable DistributedVector slots;
    /** The owned slots that other ranks' subdomains write. */
    std::vector<unsigned int> foreign_slots;
    /** The slots of owned row j: [row_slot_start[j], row_slot_start[j + 1]) (local indices). */
    std::vector<unsigned int> row_slot_start;
    /**
     * Whether the subdomains' local work runs on threads (SubdomainThreads): if every local
     * solver may solve on several threads at once.
     */
    bool threaded = false;
  };
} // namespace FetiContact
