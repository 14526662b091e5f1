#pragma once

#include <feticontact/subdomain/subdomain.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /** One coefficient of a row of B: the DoF (body vertex, component) of subdomain @p subdomain. */
  struct DualRowEntry
  {
    unsigned int subdomain;
    unsigned int body_vertex;
    unsigned int component;
    double       value;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &subdomain &body_vertex &component &value;
    }
  };

  /**
   * Rows of the constraint operator B with their right-hand side c (B u = c or B u ≤ c), stored
   * row by row with DoFs named by subdomain, body vertex and component, so that every rank can
   * extract its subdomains' blocks B_i. The rows are all rows of B, or those a rank holds (the
   * rows that touch its subdomains, rows_touching()): every row carries its number among all
   * rows, and the rows are in increasing order of their numbers.
   */
  struct DualRows
  {
    std::vector<unsigned int> row_start{0};
    std::vector<DualRowEntry> entries;
    std::vector<double>       c;
    /** The number of every row among all rows (increasing). */
    std::vector<unsigned int> number;
    /** The number of all rows, also of those that are not here. */
    unsigned int n_all = 0;
    /**
     * Sets of rows (indices here, not numbers) that one rank must hold together in the
     * distributed dual vectors (the rows of one block of a separable constraint set, e.g. a
     * contact node's normal and tangential rows); rows in no set are placed one by one.
     */
    std::vector<std::vector<unsigned int>> held_together;
    /**
     * Per set of held_together: the subdomain whose rank holds the set and adds up its rows (the
     * rows' chunk, DualProblem), or numbers::invalid_unsigned_int: the first subdomain of the
     * set's rows in their summation order.
     */
    std::vector<unsigned int> held_by;

    /** The number of rows here. */
    unsigned int
    n_rows() const
    {
      return c.size();
    }
    /** Whether these are all rows. */
    bool
    complete() const
    {
      return n_rows() == n_all;
    }
    /** Appends a row numbered n_all (one more row of all rows). */
    void
    add_row(const std::vector<DualRowEntry> &row, const double rhs);
    /** Appends row @p r of @p other with the number @p row_number. */
    void
    add_row_of(const DualRows &other, const unsigned int r, const unsigned int row_number);
    /** Appends the rows of @p other after these, renumbered after all rows of these. */
    void
    append(const DualRows &other);
    /** Appends rows @p first to @p last (exclusive) of @p other as new rows (add_row()). */
    void
    append(const DualRows &other, const unsigned int first, const unsigned int last);
    /**
     * The rows with a coefficient in a subdomain for which @p touches is true, with every row
     * held together with one of them, and, with @p keep_empty, the rows without coefficients and
     * those held together with one. Numbers and n_all are kept.
     */
    DualRows
    rows_touching(const std::function<bool(unsigned int)> &touches, const bool keep_empty) const;

    /**
     * The rows of @p parts (each with its numbers, no number in two parts) in the order of their
     * numbers, with their sets held together.
     */
    static DualRows
    merged(const std::vector<const DualRows *> &parts);

    /**
     * These rows (a rank's share of all rows, numbered) sent where they are needed, and what the
     * other ranks of @p comm send this rank: every rank gets the rows that touch its subdomains
     * (@p owner: the rank of every subdomain), each with the rows held together with it, or with
     * @p to_all every row of every rank. Collective.
     */
    DualRows
    sent_to_ranks(const MPI_Comm                   comm,
                  const std::vector<unsigned int> &owner,
                  const bool                       to_all) const;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &row_start &entries &c &number &n_all &held_together &held_by;
    }
  };

  /**
   * The equality constraints B_E u = c_E of the FETI decomposition:
   *
   * - Gluing: a vertex shared by p ≥ 2 subdomains gets, per free component, p − 1 rows that
   *   say its copies u_1 … u_p agree. They are non-redundant and orthonormal (B_E B_Eᵀ = I): row
   *   j = 1 … p − 1 is (u_1 + … + u_j − j u_{j+1}) / √(j (j + 1)) (Helmert's contrasts).
   * - TFETI (@p dirichlet_rows true): every copy of a prescribed component gets the row
   *   u = ū (a unit row), and that component gets no gluing row.
   *
   * The rows of a vertex are made by the lowest-numbered subdomain that holds it, on the rank
   * that owns it (@p owned: this rank's subdomains), and gathered on every rank of @p comm in
   * the order of bodies, vertices and components, whatever the number of ranks.
   */
  DualRows
  build_equality_rows(const MPI_Comm                  comm,
                      const std::vector<Subdomain *> &owned,
                      const bool                      dirichlet_rows);

  /**
   * The rows of build_equality_rows() that touch this rank's subdomains @p owned, with the same
   * numbers, without any rank holding all rows: the lowest holder of a vertex makes its rows,
   * the rows are numbered in the order of bodies, vertices and components by a sum over the
   * ranks (each rank counts a range of the vertices), and the maker sends the rows to the ranks
   * of the vertex's other holders. @p owner: the rank of every subdomain.
   */
  /**
   * Numbers items spread over the ranks of @p comm in the order of their @p keys (distinct over
   * all ranks): for each item, the sum of the @p sizes of all items with smaller keys, and the
   * sum of all sizes. Every rank counts the items of a range of the keys, the ranges chosen from
   * a sample of the keys so that they hold about equally many items; no rank holds all of them.
   * Collective.
   */
  std::pair<std::vector<std::uint64_t>, std::uint64_t>
  number_by_keys(const MPI_Comm                    comm,
                 const std::vector<std::uint64_t> &keys,
                 const std::vector<unsigned int>  &sizes);

  DualRows
  build_local_equality_rows(const MPI_Comm                   comm,
                            const std::vector<Subdomain *>  &owned,
                            const std::vector<unsigned int> &owner,
                            const bool                       dirichlet_rows);
} // namespace FetiContact
