#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <optional>
#include <string>

namespace FetiContact
{
  namespace Parameters
  {
    struct ContactZone;
  }

  /**
   * A rigid obstacle Ω_o that the surface Γ_c of a contact zone may touch: a closed set whose
   * surface ∂Ω_o the contact nodes must not pass. The contact search (add_obstacle_nodes()) and
   * the checks after the solve (surface_penetration(), vertex_penetration()) see an obstacle
   * through this interface only: a node x_k is held by the row n_k·u(x_k) ≤ d_k with the gap
   * d_k = signed_distance(x_k) and the critical direction n_k = −outward_normal(x_k), towards
   * the closest point χ(x_k) = closest_point(x_k) of ∂Ω_o.
   *
   * An implementation gives the signed distance and the outward normal of its surface, its name
   * and the two properties that set how its zone is searched and checked (half_space_normal(),
   * hertz_radius()); make_rigid_obstacle() makes it from the zone's parameters.
   */
  class RigidObstacle
  {
  public:
    virtual ~RigidObstacle() = default;

    /**
     * The signed distance of @p x from the surface ∂Ω_o: positive outside the obstacle,
     * negative inside.
     */
    virtual double
    signed_distance(const dealii::Point<3> &x) const = 0;

    /**
     * The unit normal of ∂Ω_o at the point closest to @p x, pointing out of the obstacle (from
     * the closest point towards @p x where @p x lies outside). Zero where the closest point is
     * not unique (a sphere's centre, a cylinder's axis).
     */
    virtual dealii::Tensor<1, 3>
    outward_normal(const dealii::Point<3> &x) const = 0;

    /**
     * The point χ(x) of ∂Ω_o closest to @p x: x − signed_distance(x) outward_normal(x) (@p x
     * itself where the normal is zero).
     */
    dealii::Point<3>
    closest_point(const dealii::Point<3> &x) const;

    /** The obstacle for messages and the log: "rigid plane", "rigid sphere", … */
    virtual std::string
    name() const = 0;

    /**
     * The outward normal if the obstacle is a half-space (a rigid plane), whose normal is the
     * same everywhere; nothing for a curved obstacle. The search of a half-space's zone takes
     * every vertex of the surface as a contact node (the zone's search distance does not apply)
     * and checks that the surface faces the normal; vertex_penetration() takes the half-spaces of
     * a body together, as the faces of one convex obstacle. A curved obstacle's zone keeps the
     * vertices within the search distance and admits nodes inside by up to it.
     */
    virtual std::optional<dealii::Tensor<1, 3>>
    half_space_normal() const = 0;

    /**
     * For the Hertz comparison (hertz_radius()): the radius R of the obstacle's surface where a
     * sphere pressed on it makes a point contact, 0 if the surface is flat (the body's spherical
     * bottom gives R); nothing if Hertz's point contact does not apply (a cylinder: a line
     * contact).
     */
    virtual std::optional<double>
    hertz_radius() const = 0;
  };

  /**
   * The half-space in front of which the body stays: the plane through the point p with the unit
   * normal n pointing out of the obstacle, signed distance (x − p)·n.
   */
  class Plane : public RigidObstacle
  {
  public:
    Plane(const dealii::Point<3> &point, const dealii::Tensor<1, 3> &normal);

    double
    signed_distance(const dealii::Point<3> &x) const override;
    dealii::Tensor<1, 3>
    outward_normal(const dealii::Point<3> &x) const override;
    std::string
    name() const override;
    std::optional<dealii::Tensor<1, 3>>
    half_space_normal() const override;
    std::optional<double>
    hertz_radius() const override;

  private:
    dealii::Point<3>     point;
    dealii::Tensor<1, 3> normal;
  };

  /** The solid ball of centre c and radius R: signed distance |x − c| − R. */
  class Sphere : public RigidObstacle
  {
  public:
    Sphere(const dealii::Point<3> &centre, const double radius);

    double
    signed_distance(const dealii::Point<3> &x) const override;
    dealii::Tensor<1, 3>
    outward_normal(const dealii::Point<3> &x) const override;
    std::string
    name() const override;
    std::optional<dealii::Tensor<1, 3>>
    half_space_normal() const override;
    std::optional<double>
    hertz_radius() const override;

  private:
    dealii::Point<3> centre;
    double           radius;
  };

  /**
   * The solid infinite cylinder of radius R around the axis through c along the unit vector a:
   * signed distance |r(x)| − R with the radial vector r(x) = (x − c) − ((x − c)·a) a.
   */
  class Cylinder : public RigidObstacle
  {
  public:
    Cylinder(const dealii::Point<3> &centre, const dealii::Tensor<1, 3> &axis, const double radius);

    double
    signed_distance(const dealii::Point<3> &x) const override;
    dealii::Tensor<1, 3>
    outward_normal(const dealii::Point<3> &x) const override;
    std::string
    name() const override;
    std::optional<dealii::Tensor<1, 3>>
    half_space_normal() const override;
    std::optional<double>
    hertz_radius() const override;

  private:
    /** The radial vector r(x) from the axis to @p x. */
    dealii::Tensor<1, 3>
    radial(const dealii::Point<3> &x) const;

    dealii::Point<3>     centre;
    dealii::Tensor<1, 3> axis;
    double               radius;
  };

  /**
   * The rigid obstacle of @p zone (a zone whose type is a rigid obstacle), from its parameters:
   * the one place that maps the parameter `Type` to a class. Parameters::ContactZone::obstacle
   * holds it after parsing.
   */
  std::shared_ptr<const RigidObstacle>
  make_rigid_obstacle(const Parameters::ContactZone &zone);
} // namespace FetiContact
