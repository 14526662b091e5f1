#pragma once

#include <feticontact/subdomain/subdomain.h>

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
   * build the same global numbering of the dual unknowns and extract its subdomains' blocks B_i.
   */
  struct DualRows
  {
    std::vector<unsigned int> row_start{0};
    std::vector<DualRowEntry> entries;
    std::vector<double>       c;
    /**
     * Sets of rows that one rank must hold together in the distributed dual vectors (the rows
     * of one block of a separable constraint set, e.g. a contact node's normal and tangential
     * rows); rows in no set are placed one by one.
     */
    std::vector<std::vector<unsigned int>> held_together;

    unsigned int
    n_rows() const
    {
      return c.size();
    }
    void
    add_row(const std::vector<DualRowEntry> &row, const double rhs);
    /** Appends all rows of @p other after these. */
    void
    append(const DualRows &other);
    /** Appends rows @p first to @p last (exclusive) of @p other after these. */
    void
    append(const DualRows &other, const unsigned int first, const unsigned int last);

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &row_start &entries &c &held_together;
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
} // namespace FetiContact
