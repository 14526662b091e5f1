#pragma once

#include <deal.II/grid/tria.h>

#include <feticontact/scene/body_parameters.h>

#include <vector>

namespace FetiContact
{
  /**
   * The split of a body's mesh into FETI subdomains: the part of every active cell (by active
   * cell index). Parts are face-connected, so that each subdomain is rigid when floating (its
   * kernel is exactly the six rigid body modes). A part that the method cuts into pieces keeps
   * its largest piece; every other piece goes to the neighbouring part with which it shares the
   * most faces (METIS and the block cut of a tetrahedral mesh leave such fragments, often single
   * cells hanging by an edge, and each would be a subdomain of its own with a nearly singular
   * coarse problem). A piece that touches no other part stays a subdomain of its own.
   */
  struct CellPartition
  {
    std::vector<unsigned int> part_of_cell;
    unsigned int              n_parts = 0;
  };

  /**
   * For every vertex of @p mesh, the parts of @p partition whose cells contain it, in increasing
   * order (empty for unused vertices). A vertex with more than one part lies on an interface.
   */
  std::vector<std::vector<unsigned int>>
  parts_of_vertices(const dealii::Triangulation<3> &mesh, const CellPartition &partition);

  /**
   * Partitions @p mesh, made as @p mesh_parameters say, as @p parameters asks (automatic,
   * structured blocks or METIS).
   */
  CellPartition
  partition_cells(const dealii::Triangulation<3>  &mesh,
                  const Parameters::Decomposition &parameters,
                  const Parameters::Mesh          &mesh_parameters,
                  const std::string               &body_name);
} // namespace FetiContact
