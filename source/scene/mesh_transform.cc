#include <deal.II/base/numbers.h>
#include <deal.II/physics/transformations.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/mesh_transform.h>

namespace FetiContact::Parameters
{
  using namespace dealii;

  Point<3>
  MeshTransform::operator()(const Point<3> &x) const
  {
    if (identity())
      return x;
    return point + rotation * (x - point) + translation;
  }

  Point<3>
  MeshTransform::to_body(const Point<3> &x) const
  {
    if (identity())
      return x;
    return point + transpose(rotation) * (x - translation - point);
  }

  void
  MeshTransform::declare_parameters(ParameterHandler &prm)
  {
    const Patterns::List vector(Patterns::Double(), 3, 3, ",");
    prm.enter_subsection("Transform");
    prm.declare_entry("Rotation axis",
                      "0, 0, 1",
                      vector,
                      "The direction a of the axis the body is rotated about (any length but "
                      "zero), right-handed: a positive angle about 0, 0, 1 turns x towards y.");
    prm.declare_entry("Rotation angle",
                      "0",
                      Patterns::Double(-360, 360),
                      "The angle θ of the rotation (degrees). 0: no rotation.");
    prm.declare_entry("Rotation point",
                      "0, 0, 0",
                      vector,
                      "A point p of the rotation axis (m, in the body's own frame).");
    prm.declare_entry("Translation",
                      "0, 0, 0",
                      vector,
                      "The translation t (m) applied after the rotation: x ↦ p + R(x − p) + t. "
                      "The mesh is generated or read, and cut into subdomains, in the body's own "
                      "frame, then moved; the surfaces named in the parameter file (such as "
                      "'z = zmax') and the box's corners and focus are in that frame, the load "
                      "and displacement vectors, the volume force and the obstacles of the "
                      "contact zones in the scene's.");
    prm.leave_subsection();
  }

  void
  MeshTransform::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Transform");
    const std::string  what = "Mesh/Transform/";
    const Tensor<1, 3> a =
      InputParsing::parse_vector(prm.get("Rotation axis"), what + "Rotation axis");
    angle       = InputParsing::parse_double(prm.get("Rotation angle"), what + "Rotation angle");
    point       = InputParsing::parse_point(prm.get("Rotation point"), what + "Rotation point");
    translation = InputParsing::parse_vector(prm.get("Translation"), what + "Translation");
    require(a.norm() > 0,
            what + "Rotation axis must not be the zero vector; got " + prm.get("Rotation axis") +
              ".");
    axis = a / a.norm();
    rotation =
      angle == 0 ?
        Tensor<2, 3>(unit_symmetric_tensor<3>()) :
        Physics::Transformations::Rotations::rotation_matrix_3d(axis, angle * numbers::PI / 180);
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters
