#include <deal.II/base/mpi.h>

#include <feticontact/base/regions.h>

#include <array>

namespace FetiContact::Regions
{
  using namespace dealii;

  bool
  meet(const BoundingBox<3> &a, const BoundingBox<3> &b)
  {
    for (unsigned int d = 0; d < 3; ++d)
      if (a.get_boundary_points().first[d] > b.get_boundary_points().second[d] ||
          b.get_boundary_points().first[d] > a.get_boundary_points().second[d])
        return false;
    return true;
  }

  void
  merge(Region &region, const BoundingBox<3> &box)
  {
    if (region)
      region->merge_with(box);
    else
      region = box;
  }

  Region
  box_of(const std::vector<Point<3>> &points)
  {
    if (points.empty())
      return {};
    return BoundingBox<3>(points);
  }

  std::vector<Region>
  of_ranks(const MPI_Comm comm, const Region &region)
  {
    std::array<double, 7> mine{};
    if (region)
      {
        mine[6] = 1;
        for (unsigned int d = 0; d < 3; ++d)
          {
            mine[d]     = region->get_boundary_points().first[d];
            mine[3 + d] = region->get_boundary_points().second[d];
          }
      }
    std::vector<Region> regions;
    for (const auto &r : Utilities::MPI::all_gather(comm, mine))
      if (r[6] == 1)
        regions.emplace_back(
          BoundingBox<3>({Point<3>(r[0], r[1], r[2]), Point<3>(r[3], r[4], r[5])}));
      else
        regions.emplace_back();
    return regions;
  }

  Region
  union_over_ranks(const MPI_Comm comm, const Region &region)
  {
    Region all;
    for (const auto &r : of_ranks(comm, region))
      if (r)
        merge(all, *r);
    return all;
  }
} // namespace FetiContact::Regions
