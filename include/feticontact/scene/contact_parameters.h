#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/scene/boundary_selector.h>

#include <string>
#include <vector>

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

    /** Body pair: the master body (0-based) and its surface, matched node by node. */
    unsigned int     master_body = 0;
    BoundarySelector master_surface;

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
