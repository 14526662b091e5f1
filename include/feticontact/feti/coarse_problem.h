#pragma once

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/block_partition.h>
#include <feticontact/feti/dual_space.h>
#include <feticontact/local_solvers/cholmod_solver.h>

#include <functional>
#include <mpi.h>
#include <vector>

namespace FetiContact
{

  /**
   * The natural coarse space of FETI: G = Rᵀ Bᵀ (one row per rigid body mode of a floating
   * subdomain, one column per dual unknown), the coarse matrix GGᵀ factorized once by CHOLMOD,
   * and the orthogonal projector P = I − Gᵀ(GGᵀ)⁻¹G onto ker G (Farhat–Mandel–Roux).
   * G is sparse and distributed by columns: a rank holds the entries of G in the columns
   * relevant to it (the rows of B that touch its subdomains, and the rows it owns). It computes
   * (G x)_a for the modes of its own subdomains from the values of x on the rows of those
   * subdomains (imported from their owners), the coarse vector is gathered, and (Gᵀy)_c is
   * computed for the rows c the rank owns, every column's terms by increasing mode. GGᵀ is
   * assembled by rows, each rank the rows of its own modes, the terms by increasing column, and
   * the rows gathered to the ranks that factorize it. Every number is summed in an order that
   * does not depend on the number of ranks, so the results are the same bits on any number.
   * Every rank must call the products together.
   *
   * The factor of GGᵀ is made and kept as FactorStorage says: by default once per node, by the
   * node's first rank, in memory the node's ranks share. The matrices (GGᵀ, and those of the
   * lower tiers in particular_solution(), whose two solves that rank makes and sends to the
   * node) are then assembled on that rank only, and a failure found there (a singular GGᵀ) is
   * thrown on every rank of the node.
   */
  class CoarseProblem
  {
  public:
    /** Where the factor of GGᵀ is stored (FETI/Coarse factor). */
    enum class FactorStorage
    {
      /**
       * Once per node: rank 0 of each node's ranks assembles GGᵀ and factorizes it, and the
       * factor goes to memory shared by the node's ranks, which all solve with it
       * (CholmodSolver::share_factor(): the same numbers as a factor per rank).
       */
      per_node,
      /** Every rank assembles and factorizes GGᵀ and keeps its own factor. */
      per_rank
    };

    /** An empty coarse problem whose factor will be kept as @p storage says. */
    explicit CoarseProblem(const FactorStorage storage = FactorStorage::per_node);
    /** Frees the communicators of set_up_node() (not collective). */
    ~CoarseProblem();
    CoarseProblem(const CoarseProblem &) = delete;
    CoarseProblem &
    operator=(const CoarseProblem &) = delete;

    /** A coefficient of G: row (rigid mode), column (dual unknown), value. */
    struct Entry
    {
      unsigned int mode;
      unsigned int column;
      double       value;

      /** For Utilities::MPI::some_to_some. */
      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &mode &column &value;
      }
    };

    /**
     * @p relevant_entries are all entries of G in the columns relevant to this rank of
     * @p space (from every rank that computes them), @p first_mode … @p end_mode this
     * rank's modes (the ranks' ranges follow each other in rank order). Collective. Throws
     * InputError if GGᵀ is singular: some rigid motion is not restrained by B. @p space
     * must outlive this object.
     */
    void
    initialize(const DualSpace   &space,
               std::vector<Entry> relevant_entries,
               const unsigned int n_modes,
               const unsigned int n_columns,
               const unsigned int first_mode,
               const unsigned int end_mode);

    unsigned int
    n_modes() const
    {
      return n_rows;
    }

    /** The number of entries of G this rank holds (those of its relevant columns). */
    std::size_t
    n_entries() const
    {
      return relevant_value.size();
    }

    /** y = G x. */
    void
    apply_G(const DualVector &x, dealii::Vector<double> &y) const;
    /** y = Gᵀ x. */
    void
    apply_Gt(const dealii::Vector<double> &x, DualVector &y) const;
    /**
     * y = G̃x with G̃ = L⁻¹PG, where P GGᵀ Pᵀ = LLᵀ is the coarse factorization: G̃ has the row
     * space of G and orthonormal rows (G̃G̃ᵀ = I), so Gλ = e ⟺ G̃λ = ẽ with ẽ = L⁻¹Pe. The
     * augmented Lagrangian works with G̃ (Dostál's orthonormalized constraints).
     */
    void
    apply_G_orthonormal(const DualVector &x, dealii::Vector<double> &y) const;
    /** y = G̃ᵀx. */
    void
    apply_Gt_orthonormal(const dealii::Vector<double> &x, DualVector &y) const;
    /** μ = PᵀL⁻ᵀμ̃: the multiplier of Gλ = e from that of G̃λ = ẽ (Gᵀμ = G̃ᵀμ̃). */
    dealii::Vector<double>
    multiplier_from_orthonormal(const dealii::Vector<double> &mu_tilde) const;
    /**
     * v ← L⁻¹P v, or with @p transpose v ← PᵀL⁻ᵀ v: the factor that orthonormalizes G
     * (QP::Orthonormalization gets it from here).
     */
    void
    apply_orthonormalizing_factor(dealii::Vector<double> &v, const bool transpose) const;
    /** ẽ = L⁻¹P e. */
    dealii::Vector<double>
    orthonormal_rhs(const dealii::Vector<double> &e) const;
    /** x ← (GGᵀ)⁻¹ x. */
    void
    solve_GGt(dealii::Vector<double> &x) const;
    /** x ← P x = x − Gᵀ(GGᵀ)⁻¹G x. */
    void
    project(DualVector &x) const;
    /** @p lambda ← the least-norm solution λ₀ = Gᵀ(GGᵀ)⁻¹e of Gλ = e. */
    void
    least_norm_solution(const dealii::Vector<double> &e, DualVector &lambda) const;
    /**
     * @p lambda ← a particular solution λ₀ of Gλ = e that leaves as many kinds of dual unknowns at
     * zero as the constraints allow. @p tier gives each column a rank (for contact: 0 gluing and
     * Dirichlet rows, 1 normal, 2 tangential); λ₀ is the least-norm solution among the columns
     * of tier ≤ t for the smallest t whose columns alone restrain every rigid mode (G_t G_tᵀ
     * nonsingular), and the least-norm solution of all of G if none does.
     *
     * @p tier is called for the columns this rank owns.
     *
     * Why it matters: the contact QP works with λ̃ = λ − λ₀, so λ₀ on a contact row moves the
     * bound λ̃_N ≥ −λ₀_N and the centre of the friction disc to −λ₀_T. A disc of radius r
     * centred at c is resolved in floating point only to ε‖c‖ (seen: r = 1.7e-9 at ‖c‖ = 3e6
     * on the brick lifted off its foundation, where MPGP stalled at every step). With λ₀ = 0
     * on the contact rows the bounds are λ̃_N ≥ 0 and the discs are centred at the origin.
     */
    void
    particular_solution(const dealii::Vector<double>                    &e,
                        const std::function<unsigned int(unsigned int)> &tier,
                        DualVector                                      &lambda) const;
    /**
     * λ ← λ + Gᵀ(GGᵀ)⁻¹(e − Gλ): removes the drift from Gλ = e that rounding accumulates over
     * many projected iterations (without it the force balance of floating subdomains is off by
     * about ‖Gλ − e‖/‖e‖, seen here up to 1e-10 after 150 iterations). Returns ‖Gλ − e‖/‖e‖ before
     * the correction.
     */
    double
    restore_feasibility(DualVector &lambda, const dealii::Vector<double> &e) const;

    /** α = (GGᵀ)⁻¹ G x (the coefficients of the rigid modes in the primal recovery). */
    dealii::Vector<double>
    coarse_coefficients(const DualVector &x) const;

    /**
     * The bytes of the factor of GGᵀ in memory shared by the ranks of this rank's node (0 if the
     * factor is the rank's own).
     */
    std::size_t
    shared_factor_bytes() const
    {
      return GGt.shared_bytes();
    }

  private:
    /**
     * With the factor stored per node (and more than one rank on the node): the ranks of this
     * rank's node, and the communicator of the nodes' first ranks (MPI_COMM_NULL elsewhere).
     * Collective on @p comm.
     */
    void
    set_up_node(const MPI_Comm comm);
    /** Whether this rank assembles and factorizes the matrices of the coarse problem. */
    bool
    factorizes() const
    {
      return node == MPI_COMM_NULL || leaders != MPI_COMM_NULL;
    }
    /**
     * Runs @p work on the ranks that factorize and returns its result on every rank of the node;
     * an exception thrown by @p work is thrown on every rank of the node (InputError stays
     * InputError). Collective on the node.
     */
    bool
    on_factorizing_rank(const std::function<bool()> &work) const;
    /** Makes the factor of @p solver, made on the node's first rank, the node's (per_node). */
    void
    share(CholmodSolver &solver) const;
    /**
     * Prepares the products: this rank owns the dual vectors' entries of @p space and
     * computes the modes [@p first_mode, @p end_mode) of G x (those of its subdomains, whose
     * columns are all relevant rows). Collective.
     */
    void
    distribute(const DualSpace &space, const unsigned int first_mode, const unsigned int end_mode);
    /** y = Gᵀx, or y += Gᵀx if @p add (each column summed in the order of increasing mode). */
    void
    add_Gt(const dealii::Vector<double> &x, const bool add, DualVector &y) const;
    /**
     * Checks GGᵀ = @p M (every mode restrained, nonsingular, well conditioned) and factorizes it,
     * on the ranks that factorize (@p M is empty elsewhere); then shares the factor (per node).
     */
    void
    factorize_GGt(const dealii::SparseMatrix<double> &M);
    /** The tiers of the columns (a bit per tier, over all ranks). */
    unsigned int
    tiers_present(const std::function<unsigned int(unsigned int)> &tier) const;
    /**
     * M = G_S G_Sᵀ over the columns S for which @p use_column holds, with its @p sparsity, on the
     * ranks that factorize (nothing elsewhere): each rank its modes' rows from its relevant
     * columns, gathered. Collective.
     */
    void
    assemble_GGt(const std::function<bool(unsigned int)> &use_column,
                 dealii::SparsityPattern                 &sparsity,
                 dealii::SparseMatrix<double>            &M) const;

    unsigned int n_rows = 0, n_cols = 0;
    /** G by the rows of this rank's modes, columns increasing (CSR over all modes). */
    std::vector<unsigned int>      row_start, column;
    std::vector<double>            value;
    CholmodSolver                  GGt;
    mutable dealii::Vector<double> work;
    /** Where the factor of GGᵀ is kept. */
    FactorStorage storage;
    /**
     * The ranks of this rank's node and the nodes' first ranks (set_up_node()); MPI_COMM_NULL
     * with the factor per rank or one rank per node.
     */
    MPI_Comm node = MPI_COMM_NULL, leaders = MPI_COMM_NULL;

    /** The space of the dual vectors (initialize()). */
    const DualSpace *space = nullptr;
    /** The ranks' ranges of modes for G x on distributed vectors. */
    BlockPartition own_modes;
    /** For the entries of G in this rank's modes: the local index of their column (owned or ghost).
     */
    std::vector<unsigned int> own_mode_column;
    /** G by the columns this rank owns (CSC in the order of the local entries, modes increasing).
     */
    std::vector<unsigned int> own_column_start, own_column_mode;
    std::vector<double>       own_column_value;
    /**
     * The relevant columns (increasing) with their entries by increasing mode (CSC: start, mode,
     * value).
     */
    std::vector<unsigned int> relevant_column, relevant_start, relevant_mode;
    std::vector<double>       relevant_value;
  };
} // namespace FetiContact
