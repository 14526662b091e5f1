#pragma once

#include <deal.II/base/bounding_box.h>

#include <mpi.h>
#include <optional>
#include <vector>

namespace FetiContact::Regions
{
  /**
   * A region of space as a rank describes what it needs of the other ranks' surfaces: an
   * axis-aligned box, or nothing.
   */
  using Region = std::optional<dealii::BoundingBox<3>>;

  /** Whether the closed boxes @p a and @p b have a point in common. */
  bool
  meet(const dealii::BoundingBox<3> &a, const dealii::BoundingBox<3> &b);

  /** @p region grown by the box @p box (or set to it). */
  void
  merge(Region &region, const dealii::BoundingBox<3> &box);

  /** The bounding box of @p points, or nothing if there are none. */
  Region
  box_of(const std::vector<dealii::Point<3>> &points);

  /** The region of every rank of @p comm, in rank order (seven doubles each). Collective. */
  std::vector<Region>
  of_ranks(const MPI_Comm comm, const Region &region);

  /** The bounding box of the regions of all ranks of @p comm. Collective. */
  Region
  union_over_ranks(const MPI_Comm comm, const Region &region);
} // namespace FetiContact::Regions
