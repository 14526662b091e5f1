#pragma once

#include <deal.II/base/array_view.h>
#include <deal.II/base/point.h>
#include <deal.II/base/types.h>

#include <array>
#include <boost/serialization/array.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>
#include <utility>
#include <vector>

namespace FetiContact
{
  /**
   * The cells of one part of a body's partition with everything that the subdomain built on them
   * needs to know of the rest of the body: the body's numbers of their vertices, the boundary ids
   * of their faces on the body's boundary, and which other parts hold each vertex. It is what a
   * rank needs to build a subdomain it owns, without the body's mesh.
   *
   * The vertices are numbered locally, in the order in which the cells first use them.
   */
  struct PartCells
  {
    /** The part of the body's partition. */
    unsigned int part = 0;
    /** Per vertex: its position and its number in the body's mesh. */
    std::vector<dealii::Point<3>> points;
    std::vector<unsigned int>     body_vertex;
    /** Per vertex: the parts whose cells contain it, in increasing order (CSR). */
    std::vector<unsigned int> holder_start{0};
    std::vector<unsigned int> holder_parts;
    /** The tetrahedra, by local vertex number, in the order of the body's active cells. */
    std::vector<std::array<unsigned int, 4>> cells;
    /** Per tetrahedron: its active cell index in the body's mesh. */
    std::vector<unsigned int> body_cell;
    /** The faces on the body's boundary: local vertex numbers (increasing) and boundary id. */
    std::vector<std::pair<std::array<unsigned int, 3>, dealii::types::boundary_id>> boundary_faces;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &part &points &body_vertex &holder_start &holder_parts &cells &body_cell
        &boundary_faces;
    }

    /** Appends a vertex: its position, its number in the body and the parts that hold it. */
    void
    add_vertex(const dealii::Point<3>          &x,
               const unsigned int               number,
               const std::vector<unsigned int> &holders)
    {
      points.push_back(x);
      body_vertex.push_back(number);
      holder_parts.insert(holder_parts.end(), holders.begin(), holders.end());
      holder_start.push_back(holder_parts.size());
    }

    /** The number of vertices. */
    unsigned int
    n_vertices() const
    {
      return points.size();
    }

    /** The parts that hold vertex @p v (this part among them), in increasing order. */
    dealii::ArrayView<const unsigned int>
    holders(const unsigned int v) const
    {
      return {holder_parts.data() + holder_start[v], holder_start[v + 1] - holder_start[v]};
    }
  };
} // namespace FetiContact
