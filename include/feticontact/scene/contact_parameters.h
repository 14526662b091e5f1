#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/scene/boundary_selector.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace FetiContact
{
  class RigidObstacle;
}

namespace FetiContact::Parameters
{
  /**
   * `subsection Zone N` of `subsection Contact`: a candidate contact surface Γ_c of one body
   * (the slave) against a rigid plane or against a surface of another body (the master), with
   * its coefficient of friction F.
   */
  struct ContactZone
  {
    enum class Type
    {
      rigid_plane,
      rigid_sphere,
      rigid_cylinder,
      body
    };
    Type type = Type::rigid_plane;

    /** The slave body (0-based) and its candidate contact surface. */
    unsigned int     body = 0;
    BoundarySelector surface;

    /** Coulomb's coefficient of friction F ≥ 0 (0: frictionless, no tangential rows). */
    double friction_coefficient = 0;

    /** Rigid plane: a point of it and its unit normal pointing out of the obstacle. */
    dealii::Point<3>     plane_point;
    dealii::Tensor<1, 3> plane_normal;

    /**
     * Rigid sphere and rigid cylinder: the centre (a point of the cylinder's axis), the unit
     * direction of the cylinder's axis and the radius. The obstacle is the solid ball or the solid
     * infinite cylinder.
     */
    dealii::Point<3>     centre;
    dealii::Tensor<1, 3> axis;
    double               radius = 0;

    /** Whether the obstacle is rigid (a plane, a sphere or a cylinder). */
    bool
    rigid() const
    {
      return type != Type::body;
    }

    /**
     * A rigid obstacle's geometry (make_rigid_obstacle() of the parameters above, set by
     * parse_parameters()); null for a body pair.
     */
    std::shared_ptr<const RigidObstacle> obstacle;

    /** Body pair: the master body (0-based) and its surface. */
    unsigned int     master_body = 0;
    BoundarySelector master_surface;

    /** Body pair: how the rows couple the two surfaces. */
    enum class Discretization
    {
      /** Node to node where the surfaces match node for node, mortar otherwise. */
      automatic,
      /** Each slave node against the master vertex opposite it (matching meshes only). */
      node_to_node,
      /** Dual mortar rows (non-matching meshes). */
      mortar
    };
    Discretization discretization = Discretization::automatic;
    /**
     * Body pair: how far in front of a slave triangle a master triangle is still coupled with it,
     * and how deep it may lie behind it initially (m); empty: the mean edge length of the slave
     * surface. Rigid sphere and cylinder: nodes farther from the obstacle are not contact nodes,
     * and nodes up to this deep inside it initially are pushed out by the solve; empty: every
     * node is a contact node and none may start inside.
     */
    std::optional<double> search_distance;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    /** @p n_bodies: to check the body numbers. */
    void
    parse_parameters(dealii::ParameterHandler &prm, const unsigned int n_bodies);
  };

  /** `subsection Contact`: the contact zones of the scene. */
  struct Contact
  {
    std::vector<ContactZone> zones;

    static void
    declare_parameters(dealii::ParameterHandler &prm, const unsigned int n_zones);
    void
    parse_parameters(dealii::ParameterHandler &prm, const unsigned int n_bodies);
  };
} // namespace FetiContact::Parameters

namespace FetiContact
{
  /** Whether body @p b (0-based) has a contact surface or is the master of one. */
  bool
  in_contact(const Parameters::Contact &contact, const unsigned int b);
} // namespace FetiContact
