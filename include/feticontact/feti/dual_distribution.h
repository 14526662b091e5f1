#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/base/distributed_vector.h>

#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * How the dual unknowns (the rows of B) are spread over the MPI ranks: every rank owns some
   * rows (the entries of its DistributedVector dual vectors) and needs the values of more, the
   * relevant rows: all rows of B that touch its subdomains (Bᵀλ on a subdomain, G λ for its rigid
   * modes). The rows a rank needs but does not own are its ghosts; import() gets their values
   * from their owners, point to point (only ranks whose subdomains share rows exchange anything).
   *
   * Knows nothing of FETI beyond row numbers: DualProblem decides which rank owns a row.
   */
  class DualDistribution
  {
  public:
    /**
     * @p owned_rows: the rows this rank owns, increasing; @p relevant_rows: the rows it needs,
     * increasing, a superset of the owned ones, and @p relevant_owner the rank that owns each;
     * @p n_rows: the number of all rows. Collective (one exchange of the ghost lists with their
     * owners). @p chunk_of_owned_row: the chunk of every owned row for the sums of the dual
     * vectors (DistributedVector::Layout).
     */
    DualDistribution(const MPI_Comm                   comm,
                     const std::vector<unsigned int> &owned_rows,
                     const std::vector<unsigned int> &relevant_rows,
                     const std::vector<int>          &relevant_owner,
                     const unsigned int               n_rows,
                     const std::vector<unsigned int> &chunk_of_owned_row = {});

    /** The layout of the dual vectors (the owned rows in increasing order). */
    const std::shared_ptr<const DistributedVector::Layout> &
    layout() const
    {
      return vector_layout;
    }

    /** A zero dual vector. */
    DistributedVector
    vector() const
    {
      return DistributedVector(vector_layout);
    }

    /** The relevant rows (increasing). */
    const std::vector<unsigned int> &
    relevant_rows() const
    {
      return relevant;
    }

    /** The relevant index of every owned row, in the order of the local entries. */
    const std::vector<unsigned int> &
    owned_relevant_indices() const
    {
      return owned_relevant;
    }

    /** The index of relevant row @p row among the relevant rows (binary search). */
    unsigned int
    relevant_index(const unsigned int row) const;

    /**
     * @p values ← the values of @p x on the relevant rows (owned ones copied, ghosts received
     * from their owners). Collective among neighbours.
     */
    void
    import(const DistributedVector &x, dealii::Vector<double> &values) const;

    /** The owned entries of a vector of all rows. */
    DistributedVector restrict(const dealii::Vector<double> &all) const;

    /**
     * All rows of @p x on every rank (MPI_Allgatherv). For tests and the shared local work,
     * which need a global view; collective (the first call also gathers the rows' numbers).
     */
    dealii::Vector<double>
    gather(const DistributedVector &x) const;

    /** The number of neighbour ranks this rank receives ghost values from. */
    unsigned int
    n_neighbours() const
    {
      return receive.size();
    }

    /** The numbers of values this rank sends and receives in one import(). */
    std::size_t
    n_sent() const;
    std::size_t
    n_received() const;

  private:
    /** The values exchanged with one other rank: local or relevant indices, and a buffer. */
    struct Exchange
    {
      int                         rank;
      std::vector<unsigned int>   index;
      mutable std::vector<double> buffer;
    };

    MPI_Comm                                         comm;
    std::shared_ptr<const DistributedVector::Layout> vector_layout;
    std::vector<unsigned int>                        relevant;
    /** The relevant index of every owned row (in the order of the local entries). */
    std::vector<unsigned int> owned_relevant;
    /** send: local indices of owned rows; receive: relevant indices of ghosts. */
    std::vector<Exchange>            send, receive;
    mutable std::vector<MPI_Request> requests;
    /**
     * For gather(), made at its first call: the numbers of owned rows of every rank, where they
     * start, and every rank's rows.
     */
    mutable std::vector<int>          gather_count, gather_displacement;
    mutable std::vector<unsigned int> gathered_rows;
  };
} // namespace FetiContact
