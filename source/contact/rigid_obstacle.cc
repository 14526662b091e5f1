#include <feticontact/contact/rigid_obstacle.h>
#include <feticontact/scene/contact_parameters.h>

namespace FetiContact
{
  using namespace dealii;

  Point<3>
  RigidObstacle::closest_point(const Point<3> &x) const
  {
    return x - signed_distance(x) * outward_normal(x);
  }

  Plane::Plane(const Point<3> &point, const Tensor<1, 3> &normal)
    : point(point)
    , normal(normal)
  {}

  double
  Plane::signed_distance(const Point<3> &x) const
  {
    return (x - point) * normal;
  }

  Tensor<1, 3>
  Plane::outward_normal(const Point<3> &) const
  {
    return normal;
  }

  std::string
  Plane::name() const
  {
    return "rigid plane";
  }

  std::optional<Tensor<1, 3>>
  Plane::half_space_normal() const
  {
    return normal;
  }

  std::optional<double>
  Plane::hertz_radius() const
  {
    return 0.;
  }

  Sphere::Sphere(const Point<3> &centre, const double radius)
    : centre(centre)
    , radius(radius)
  {}

  double
  Sphere::signed_distance(const Point<3> &x) const
  {
    const Tensor<1, 3> v = x - centre;
    return v.norm() - radius;
  }

  Tensor<1, 3>
  Sphere::outward_normal(const Point<3> &x) const
  {
    const Tensor<1, 3> v = x - centre;
    const double       r = v.norm();
    return r > 0 ? Tensor<1, 3>(v / r) : Tensor<1, 3>();
  }

  std::string
  Sphere::name() const
  {
    return "rigid sphere";
  }

  std::optional<Tensor<1, 3>>
  Sphere::half_space_normal() const
  {
    return {};
  }

  std::optional<double>
  Sphere::hertz_radius() const
  {
    return radius;
  }

  Cylinder::Cylinder(const Point<3> &centre, const Tensor<1, 3> &axis, const double radius)
    : centre(centre)
    , axis(axis)
    , radius(radius)
  {}

  Tensor<1, 3>
  Cylinder::radial(const Point<3> &x) const
  {
    Tensor<1, 3> v = x - centre;
    v -= (v * axis) * axis;
    return v;
  }

  double
  Cylinder::signed_distance(const Point<3> &x) const
  {
    return radial(x).norm() - radius;
  }

  Tensor<1, 3>
  Cylinder::outward_normal(const Point<3> &x) const
  {
    const Tensor<1, 3> v = radial(x);
    const double       r = v.norm();
    return r > 0 ? Tensor<1, 3>(v / r) : Tensor<1, 3>();
  }

  std::string
  Cylinder::name() const
  {
    return "rigid cylinder";
  }

  std::optional<Tensor<1, 3>>
  Cylinder::half_space_normal() const
  {
    return {};
  }

  std::optional<double>
  Cylinder::hertz_radius() const
  {
    return {};
  }

  std::shared_ptr<const RigidObstacle>
  make_rigid_obstacle(const Parameters::ContactZone &zone)
  {
    using Type = Parameters::ContactZone::Type;
    switch (zone.type)
      {
        case Type::rigid_plane:
          return std::make_shared<Plane>(zone.plane_point, zone.plane_normal);
        case Type::rigid_sphere:
          return std::make_shared<Sphere>(zone.centre, zone.radius);
        case Type::rigid_cylinder:
          return std::make_shared<Cylinder>(zone.centre, zone.axis, zone.radius);
        case Type::body:
          break;
      }
    return nullptr;
  }
} // namespace FetiContact
