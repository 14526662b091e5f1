#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

namespace FetiContact::Parameters
{
  /**
   * `subsection Transform` of `subsection Mesh`: the rigid motion that places a body, given in
   * its own frame (a generated box or the coordinates of a Gmsh file), in the scene,
   * x ↦ p + R (x − p) + t, with R the rotation by the angle θ about the axis a (right-handed)
   * through the point p, followed by the translation t. The identity by default.
   *
   * It applies to the mesh after it is generated or read and partitioned; what the parameter file
   * says of the body's boundary (the surface selectors `z = zmax`, boundary ids) and its
   * generation (corners, focus, decomposition blocks) is in the body's own frame, while load and
   * displacement vectors and the obstacles are in the scene's (global) frame.
   */
  struct MeshTransform
  {
    /** The unit rotation axis a (of the parameter file, normalized). */
    dealii::Tensor<1, 3> axis;
    /** θ in degrees, as given. */
    double angle = 0;
    /** p, the point the axis passes through. */
    dealii::Point<3> point;
    /** t. */
    dealii::Tensor<1, 3> translation;
    /** R. */
    dealii::Tensor<2, 3> rotation = dealii::unit_symmetric_tensor<3>();

    /** Whether the transform is the identity (θ = 0 and t = 0). */
    bool
    identity() const
    {
      return angle == 0 && translation.norm() == 0;
    }

    /** The point @p x of the body's own frame in the scene: p + R (x − p) + t. */
    dealii::Point<3>
    operator()(const dealii::Point<3> &x) const;

    /** The point @p x of the scene in the body's own frame: p + Rᵀ (x − t − p). */
    dealii::Point<3>
    to_body(const dealii::Point<3> &x) const;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
