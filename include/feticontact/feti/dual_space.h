#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/base/reproducible_partitioner.h>

#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /** The type of the dual vectors λ (and of h, c, F λ and the QP's work vectors). */
  using DualVector = DistributedVector;

  /**
   * The space of the dual unknowns (the rows of B) spread over the MPI ranks: deal.II's
   * distributed vectors on a ReproduciblePartitioner. A row is known to the caller by its number
   * (its key); its index in the vectors numbers the rows by their chunk (the first subdomain in
   * their summation order, whose rank owns them), then by number: the same numbering on any
   * number of ranks, and every rank owns a contiguous range. The rows a rank needs but does not
   * own (those that touch its subdomains) are its ghosts: DistributedVector::update_ghost_values()
   * fetches them, and local_index() finds a row among the owned and ghost entries.
   *
   * Knows nothing of FETI beyond row numbers: DualProblem decides which rank owns a row.
   */
  class DualSpace
  {
  public:
    /**
     * @p owned_rows: the numbers of the rows this rank owns, with the chunk of each
     * (@p chunk_of_owned_row; the chunks of a rank follow those of the ranks before it);
     * @p ghost_rows: the rows it needs from other ranks (increasing) and @p ghost_owner the rank
     * of each; @p n_rows the number of all rows. Collective.
     */
    DualSpace(const MPI_Comm                   comm,
              const std::vector<unsigned int> &owned_rows,
              const std::vector<unsigned int> &chunk_of_owned_row,
              const std::vector<unsigned int> &ghost_rows,
              const std::vector<int>          &ghost_owner,
              const unsigned int               n_rows);

    /** The partitioner of the dual vectors. */
    const std::shared_ptr<const ReproduciblePartitioner> &
    partitioner() const
    {
      return row_partitioner;
    }

    /** A zero dual vector. */
    DualVector
    vector() const;

    /** The number of the row of owned entry @p i. */
    unsigned int
    row(const unsigned int i) const
    {
      return row_partitioner->key(i);
    }

    /** The number of rows this rank owns. */
    unsigned int
    n_owned() const
    {
      return row_partitioner->locally_owned_size();
    }

    /**
     * The local index of row @p row among the owned and ghost entries of a dual vector, or
     * numbers::invalid_unsigned_int if it is neither.
     */
    unsigned int
    local_index(const unsigned int row) const;

    /** The local index of row @p row if this rank owns it, or numbers::invalid_unsigned_int. */
    unsigned int
    owned_index(const unsigned int row) const;

    /** The index of row @p row in the dual vectors, if this rank owns it or it is a ghost. */
    dealii::types::global_dof_index
    global_index(const unsigned int row) const;

    /** The owned entries of a vector of all rows (indexed by row number). */
    DualVector restrict(const dealii::Vector<double> &all) const;

    /** All rows of @p x (indexed by row number) on every rank (MPI_Allgatherv). Collective. */
    dealii::Vector<double>
    gather(const DualVector &x) const;

  private:
    MPI_Comm                                       comm;
    std::shared_ptr<const ReproduciblePartitioner> row_partitioner;
    /** The row numbers of the owned and ghost entries (increasing) and their local indices. */
    std::vector<unsigned int> known_rows, known_local;
  };
} // namespace FetiContact
