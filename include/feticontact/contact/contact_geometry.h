#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/scene/body.h>
#include <feticontact/scene/contact_parameters.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace FetiContact
{
  /**
   * A contact node x_k of a slave surface Γ_c (doc/formulation.md, "The continuous problem"): the
   * vertex, its partner χ(x_k) (a vertex of the master surface, or the projection on a rigid
   * plane), the critical direction n_k, tangents t1_k, t2_k ({n, t1, t2} orthonormal), the initial
   * gap d_k = (χ(x_k) − x_k)·n_k and the coefficient of friction F of its zone.
   */
  struct ContactNode
  {
    unsigned int zone;
    unsigned int body;
    unsigned int vertex;
    /** Body pair: the master body and vertex χ(x_k); empty for a rigid obstacle. */
    std::optional<std::pair<unsigned int, unsigned int>> master;
    dealii::Point<3>                                     x;
    dealii::Tensor<1, 3>                                 n, t1, t2;
    double                                               gap;
    double                                               friction;
    /**
     * The area of the slave surface lumped at the node (a third of each adjacent triangle):
     * λ_N / area is the mean contact pressure around the node.
     */
    double area = 0;
    /**
     * For a node at a vertex shared with other zones whose tangential rows another node of the
     * vertex carries (combine_shared_vertices): that node's index. This node's μ λ_N adds to
     * that node's slip bound (slip_bounds()).
     */
    std::optional<unsigned int> keeper;
  };

  /** A triangle of a zone's slave surface (body-mesh vertices), for output. */
  struct ContactTriangle
  {
    unsigned int                zone;
    unsigned int                body;
    std::array<unsigned int, 3> vertices;
  };

  /**
   * The contact nodes of all zones: the vertices of each zone's surface that have no prescribed
   * displacement component, or only components orthogonal to the node's normal, such as a
   * symmetry plane's roller condition (then t2 is the last prescribed axis, whose tangential row
   * acts on no free DoF), in zone order and by vertex number. A vertex on the surfaces of several
   * zones is a node of each (see combine_shared_vertices in contact_geometry.cc: the first keeps
   * the tangents orthogonal to all normals of the vertex, the others none). Rigid plane: χ(x_k) is
   * the orthogonal projection of x_k on the plane and n_k the plane's normal pointing into the
   * obstacle. Body pair: n_k is from x_k towards χ(x_k) when the gap is positive and the outer unit
   * normal of Γ_c (the area-weighted mean of the adjacent face normals) when it is zero. For a body
   * pair every slave node must have a master vertex opposite it along its normal; otherwise the
   * surfaces do not match and InputError names the node. If @p triangles is given, the triangles of
   * every zone's surface are appended to it (for the contact-surface output).
   */
  std::vector<ContactNode>
  find_contact_nodes(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     std::vector<ContactTriangle>             *triangles = nullptr);

  /** Unit vectors t1, t2 completing the unit vector n to a right-handed orthonormal basis. */
  std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>>
  tangent_basis(const dealii::Tensor<1, 3> &n);
  /**
   * The Coulomb slip bounds of the nodes in the units of the forces, from their normal forces
   * @p normal_force: g_k = F_k (λ_N,k)⁺ plus, at a vertex shared by several zones, F_j (λ_N,j)⁺
   * of every node j whose keeper is k (the friction of every zone acts along the directions
   * that the keeper's tangential rows span).
   */
  std::vector<double>
  slip_bounds(const std::vector<ContactNode> &nodes, const std::vector<double> &normal_force);
} // namespace FetiContact
