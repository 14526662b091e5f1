#pragma once

#include <feticontact/scene/body.h>

#include <memory>
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
   * Subdomains are numbered globally: body b's part p is subdomain first_subdomain[b] + p.
   */
  DualRows
  build_equality_rows(const std::vector<std::unique_ptr<Body>> &bodies,
                      const std::vector<unsigned int>          &first_subdomain,
                      const bool                                dirichlet_rows);
} // namespace FetiContact
