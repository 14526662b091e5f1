#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_distribution.h>
#include <feticontact/feti/equality_constraints.h>
#include <feticontact/feti/shared_local_work.h>
#include <feticontact/subdomain/subdomain.h>

#include <memory>
#include <mpi.h>
#include <utility>
#include <vector>

namespace FetiContact
{
  /** The type of the dual vectors λ (and of h, c, F λ): replicated on every rank. */
  using DualVector = dealii::Vector<double>;

  /**
   * The FETI dual problem
   *
   *   min ½ λᵀFλ − λᵀh  s.t.  Gλ = e  (and, with contact, bounds on some components of λ)
   *
   * with F = B K⁺ Bᵀ, h = B K⁺ f − c, G = Rᵀ Bᵀ, e = Rᵀ f, assembled from the blocks B_i of the
   * subdomains that this rank owns. Dual vectors are replicated on every rank; F is applied
   * subdomain by subdomain and summed over the ranks. The sum is rank-independent: every
   * subdomain writes its terms B_i u_i into its own slots (one per nonzero of B), and every row
   * adds its slots in the order of increasing subdomain. Every row belongs to the rank of the
   * first subdomain in that order, or of the subdomain its set of rows held together names
   * (DualRows::held_by; the contact rows of a slave vertex, its home subdomain): the terms of other
   * ranks' subdomains in it (rows on the boundaries between the ranks' sets of subdomains) are sent
   * to that rank point to point, it adds up its rows, and an MPI_Allgatherv gives every rank all
   * rows. F x, h and B u − c are then the same bits on any number of ranks and any assignment of
   * subdomains to ranks, and so are the iterates and iteration counts of the solvers that use them
   * (floating-point addition is not associative: a sum in rank order made n_A differ by 8 % between
   * one and two ranks). When the ranks of a node share their local work (SharedLocalWork), the
   * slots are in shared memory, any rank may solve any subdomain, and every rank adds up all rows
   * itself; the sums are the same. Knows nothing of friction: it sees rows of B and their
   * right-hand side c.
   *
   * The same operations exist on distributed dual vectors (DistributedVector, spread over the
   * ranks by distribution()): every rank holds the rows it adds up, gets the values of the other
   * rows of its subdomains from their owners (DualDistribution::import), and F x is the same bits
   * as on replicated vectors.
   */
  class DualProblem
  {
  public:
    /**
     * @p owned: this rank's subdomains (factorized); @p mode_offset: first rigid mode of every
     * global subdomain (size n_subdomains + 1); @p rows: all rows of B with c, or, with
     * @p distributed_coarse and without @p shared, at least the rows that touch this rank's
     * subdomains (DualRows::rows_touching(), build_local_equality_rows()). With
     * @p distributed_coarse and without @p shared the rank holds nothing of the length of all
     * rows but what the coarse problem needs, and the products with replicated dual vectors
     * (those taking dealii::Vector) throw. With
     * @p shared (which holds the factors of this rank's reserve, SharedLocalWork::take_factor(),
     * and must outlive this object) the ranks of the node share the reserves' part of the local
     * work of every multiplication by F; F x is the same either way. With @p distributed_coarse
     * a rank holds G only in the columns relevant to it (CoarseProblem::initialize_distributed())
     * and only the products with distributed dual vectors exist. @p coarse_factor: where the
     * factor of GGᵀ is kept (CoarseProblem::FactorStorage).
     */
    DualProblem(
      const MPI_Comm                     comm,
      const std::vector<Subdomain *>    &owned,
      const std::vector<unsigned int>   &mode_offset,
      const DualRows                    &rows,
      SharedLocalWork                   *shared             = nullptr,
      const bool                         distributed_coarse = false,
      const CoarseProblem::FactorStorage coarse_factor = CoarseProblem::FactorStorage::per_node);

    /** The number of dual unknowns m. */
    unsigned int
    size() const
    {
      return n_all_rows;
    }

    /** y = F x (counted in n_F_applications, timed in F_time). */
    void
    apply_F(const dealii::Vector<double> &x, dealii::Vector<double> &y) const;

    /** y = F x on distributed dual vectors (the same numbers as the replicated product). */
    void
    apply_F(const DistributedVector &x, DistributedVector &y) const;

    /**
     * How the dual vectors are distributed: the rows this rank adds up (those of its first
     * subdomain in summation order) and the rows of its subdomains.
     */
    const DualDistribution &
    distribution() const
    {
      return *row_distribution;
    }

    /** What one application of F exchanges on this rank, counted in values (doubles). */
    struct CommunicationVolume
    {
      /** Ranks this rank exchanges slots with (terms B_i u_i of rows another rank adds up). */
      unsigned int slot_neighbours = 0;
      /** Slot values sent and received (point to point, both paths). */
      std::size_t slots_sent = 0, slots_received = 0;
      /** Replicated dual vectors: the other ranks' row sums (MPI_Allgatherv). */
      std::size_t gathered_values = 0;
      /** Distributed dual vectors: ranks the ghost rows come from, and their number. */
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
    apply_lumped(const dealii::Vector<double> &x, dealii::Vector<double> &y) const;

    /** The lumped preconditioner on distributed dual vectors. */
    void
    apply_lumped(const DistributedVector &x, DistributedVector &y) const;

    /**
     * The primal solution u_i = K_i⁺(f_i − B_iᵀλ) + R_i α_i of every owned subdomain, with
     * α = (GGᵀ)⁻¹G(Fλ − h) (so that B u = c holds in the least-squares sense on the range of G).
     */
    std::vector<dealii::Vector<double>>
    recover_primal(const dealii::Vector<double> &lambda) const;

    /** The same with given coefficients α of the rigid modes (e.g. from SMALBE's multiplier). */
    std::vector<dealii::Vector<double>>
    recover_primal(const dealii::Vector<double> &lambda, const dealii::Vector<double> &alpha) const;

    /** recover_primal() from a distributed λ. */
    std::vector<dealii::Vector<double>>
    recover_primal(const DistributedVector &lambda) const;

    /** recover_primal() from a distributed λ and given α. */
    std::vector<dealii::Vector<double>>
    recover_primal(const DistributedVector &lambda, const dealii::Vector<double> &alpha) const;

    /** r = B u − c from the subdomain solutions of this rank, summed over the ranks. */
    dealii::Vector<double>
    constraint_residual(const std::vector<dealii::Vector<double>> &u) const;

    /** B u − c on this rank's rows. */
    DistributedVector
    distributed_constraint_residual(const std::vector<dealii::Vector<double>> &u) const;

    CoarseProblem coarse;
    /** h and c on all rows: only with the replicated products (empty otherwise). */
    dealii::Vector<double> h, c;
    /** h and c on this rank's rows (the layout of distribution()). */
    DistributedVector h_owned, c_owned;
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
    /** The subdomain solves this rank made in apply_F (its own and from shared reserves). */
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
     * The rows of each rank and the slots that cross ranks (from the rows and the owners).
     * Owners::row_rank is given for the rows of @p rows.
     */
    Owners
    setup_row_sums(const DualRows &rows, const unsigned int n_subdomains);
    /** The owners of the subdomains and of the rows given (collective). */
    Owners
    row_owners(const DualRows &rows, const unsigned int n_subdomains) const;
    /** The slots of this rank sent to, and received from, the ranks that add up their rows. */
    void
    set_up_slot_exchanges(const DualRows &rows, const Owners &owners);
    /** This rank's rows, and for the replicated products the order of the gathered sums. */
    void
    set_up_own_rows(const DualRows &rows, const Owners &owners);
    /** The distribution of the dual vectors and the relevant index of every entry of B_i. */
    void
    set_up_distribution(const DualRows &rows, const Owners &owners);
    /** The index in @p rows of the row numbered @p number. */
    static unsigned int
    index_of_row(const DualRows &rows, const unsigned int number);
    /** c_owned and h_owned, and with the replicated products c and h (from the slots of B K⁺f). */
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
    /**
     * y = the sum over the ranks of the slots, row by row in the order of increasing subdomain
     * (each rank its rows, then gathered).
     */
    void
    sum_slots(dealii::Vector<double> &y) const;
    void
    set_Bt(const unsigned int            i,
           const dealii::Vector<double> &lambda,
           dealii::Vector<double>       &x) const;
    /** x = B_iᵀ λ from the values of λ on the relevant rows (DualDistribution::import). */
    void
    set_Bt_relevant(const unsigned int            i,
                    const dealii::Vector<double> &lambda_relevant,
                    dealii::Vector<double>       &x) const;
    /**
     * Receives the slots of other ranks' subdomains in this rank's rows and sends this rank's
     * slots in other ranks' rows.
     */
    void
    exchange_slots() const;
    /** The sums of this rank's rows (after exchange_slots()), in the order of own_rows. */
    void
    sum_own_rows(double *sums) const;
    /** B_i of every owned subdomain from the rows (DoFs looked up by body vertex). */
    void
    build_blocks(const DualRows &rows);
    /**
     * The range of the rigid modes of this rank's subdomains, for G x on distributed vectors
     * (CoarseProblem::distribute): they follow each other in rank order.
     */
    std::pair<unsigned int, unsigned int>
    own_modes(const std::vector<unsigned int> &mode_offset) const;
    /** y = @p product (x) on distributed vectors through replicated ones (shared local work). */
    void
    apply_replicated(void (DualProblem::*product)(const dealii::Vector<double> &,
                                                  dealii::Vector<double> &) const,
                     const DistributedVector &x,
                     DistributedVector       &y) const;
    /** y = F x with x given on the relevant rows (the local work, then the row sums). */
    void
    apply_F_relevant(const dealii::Vector<double> &x_relevant, DistributedVector &y) const;
    /** The local part of recover_primal(): u_i = K_i⁺(f_i − B_iᵀλ) + R_i α_i. */
    std::vector<dealii::Vector<double>>
    recover_primal_relevant(const dealii::Vector<double> &lambda_relevant,
                            const dealii::Vector<double> &alpha) const;

    /** The rows of this rank's dual vectors, and the relevant rows of its subdomains. */
    std::unique_ptr<DualDistribution> row_distribution;
    /** Per owned subdomain: the relevant index of the row of every entry of B_i. */
    std::vector<std::vector<unsigned int>> relevant_row;
    /** Work vectors of the distributed products: x on the relevant rows. */
    mutable dealii::Vector<double> x_relevant;
    /** D of apply_lumped on the relevant rows. */
    mutable dealii::Vector<double> lumped_scale_relevant;

    /** D = diag(B Bᵀ)⁻¹ of apply_lumped (computed at its first call). */
    mutable dealii::Vector<double> lumped_row_scale;
    /** Work vectors of apply_lumped: D x, and K_i Bᵀ D x per owned subdomain. */
    mutable dealii::Vector<double>              lumped_Dx;
    mutable std::vector<dealii::Vector<double>> lumped_Ku;

    MPI_Comm                 comm;
    std::vector<Subdomain *> owned;
    /** The number of all rows (m). */
    unsigned int n_all_rows = 0;
    /**
     * Whether the products with replicated dual vectors exist (without @p distributed_coarse,
     * or with the shared local work): then every rank has all rows, and h and c of all rows.
     */
    bool                                        replicated_products = true;
    std::vector<BlockOfB>                       B;
    std::vector<unsigned int>                   first_mode;
    mutable std::vector<dealii::Vector<double>> work;
    /** The slots of every row in summation order (CSR: slot_start, slot_order). */
    std::vector<unsigned int> slot_start, slot_order;
    /**
     * One number per nonzero of B: B_i u_i entry by entry. This rank's blocks write their slots
     * (all of them, in every product); the slots of other ranks' subdomains in this rank's rows
     * are received before the rows are added up; the rest stay zero and are never read.
     */
    mutable std::vector<double> slots;
    /** The local work shared by the node's ranks (then the slots are its shared slots). */
    SharedLocalWork *shared = nullptr;
    /** slots.data(), or the shared slots. */
    double *slot_values = nullptr;
    /**
     * Whether the subdomains' local work runs on threads (SubdomainThreads): if every local
     * solver may solve on several threads at once.
     */
    bool threaded = false;
    /** The owned subdomains (indices into owned) that only this rank solves. */
    std::vector<unsigned int> own_work;
    /**
     * The slots exchanged with one other rank: their indices (increasing) and a buffer for
     * their values.
     */
    struct SlotExchange
    {
      int                         rank;
      std::vector<unsigned int>   slots;
      mutable std::vector<double> buffer;
    };
    bool                             single_rank = true;
    std::vector<SlotExchange>        send_slots, receive_slots;
    mutable std::vector<MPI_Request> requests;
    /**
     * This rank's rows: their numbers (increasing) and their indices in the rows given to the
     * constructor (the rows of the slots); all rows in the order of the gathered sums (only with
     * all rows on several ranks).
     */
    std::vector<unsigned int>   own_rows, own_local, gathered_rows;
    std::vector<int>            row_count, row_displacement;
    mutable std::vector<double> own_sums, gathered_sums;
  };
} // namespace FetiContact
