#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/mesh_generation.h>
#include <feticontact/subdomain/rigid_body_modes.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace FetiContact
{
  using namespace dealii;

  Body::Body(const Parameters::Body &parameters, const unsigned int index)
    : parameters(parameters)
    , index(index)
  {}

  void
  Body::setup()
  {
    MeshGeneration::create_mesh(parameters.mesh, mesh, parameters.name);

    auto &bc = parameters.boundary_conditions;
    for (auto &p : bc.prescribed_displacements)
      p.boundary.resolve(mesh, parameters.name);
    for (auto &t : bc.tractions)
      t.boundary.resolve(mesh, parameters.name);

    // Γ_u vertex by vertex; two parts that prescribe different values for the same component
    // of a vertex contradict each other.
    prescribed.clear();
    std::map<unsigned int, std::array<const Parameters::PrescribedDisplacement *, 3>> source;
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const auto &p : bc.prescribed_displacements)
            if (p.boundary.contains(*face))
              for (const unsigned int v : face->vertex_indices())
                {
                  const unsigned int vertex = face->vertex_index(v);
                  auto              &value  = prescribed[vertex];
                  auto              &from   = source[vertex];
                  for (unsigned int c = 0; c < 3; ++c)
                    if (p.value[c])
                      {
                        if (value[c] && from[c] != &p)
                          {
                            const double a = *value[c], b = *p.value[c];
                            require(std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)),
                                    "Body '" + parameters.name + "': the boundary parts <" +
                                      from[c]->boundary.name() + "> and <" + p.boundary.name() +
                                      "> prescribe different displacements (" +
                                      InputParsing::number_text(a) + " and " +
                                      InputParsing::number_text(b) + ") for component " +
                                      std::to_string(c) + " at the vertex they share.");
                          }
                        value[c] = p.value[c];
                        from[c]  = &p;
                      }
                }

    partition = partition_cells(mesh, parameters.decomposition, parameters.mesh, parameters.name);
    cells_of_part.assign(partition.n_parts, {});
    for (const auto &cell : mesh.active_cell_iterators())
      cells_of_part[partition.part_of_cell[cell->active_cell_index()]].push_back(cell);
  }

  PartCells
  Body::part_cells(const unsigned int                            part,
                   const std::vector<std::vector<unsigned int>> &parts_of_vertex) const
  {
    // (A map, not a vector over all vertices of the body: that would be quadratic in the number
    // of parts.)
    PartCells                                      result;
    std::unordered_map<unsigned int, unsigned int> local_vertex;
    result.part = part;
    for (const auto &cell : cells_of_part[part])
      {
        std::array<unsigned int, 4> local;
        for (const unsigned int v : cell->vertex_indices())
          {
            const unsigned int body_vertex = cell->vertex_index(v);
            const auto [entry, first_seen] =
              local_vertex.emplace(body_vertex, result.points.size());
            if (first_seen)
              {
                result.points.push_back(cell->vertex(v));
                result.body_vertex.push_back(body_vertex);
                const auto &holders = parts_of_vertex[body_vertex];
                result.holder_parts.insert(result.holder_parts.end(),
                                           holders.begin(),
                                           holders.end());
                result.holder_start.push_back(result.holder_parts.size());
              }
            local[v] = entry->second;
          }
        result.cells.push_back(local);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              std::array<unsigned int, 3> key;
              for (unsigned int v = 0; v < 3; ++v)
                key[v] = local_vertex.at(face->vertex_index(v));
              std::sort(key.begin(), key.end());
              result.boundary_faces.emplace_back(key, face->boundary_id());
            }
      }
    return result;
  }

  PartCells
  Body::part_cells(const unsigned int part) const
  {
    return part_cells(part, parts_of_vertices(mesh, partition));
  }

  Tensor<1, 3>
  FreeRigidMotions::value(const unsigned int j, const Point<3> &x) const
  {
    const Tensor<1, 3> r = (x - centre) / length;
    Tensor<1, 3>       v;
    for (unsigned int i = 0; i < 3; ++i)
      {
        Tensor<1, 3> e;
        e[i] = 1;
        v += coefficients(i, j) * e + coefficients(i + 3, j) * cross_product_3d(e, r);
      }
    return v;
  }

  FreeRigidMotions
  Body::free_rigid_motions() const
  {
    FreeRigidMotions motions;
    Point<3>         lower, upper;
    unsigned int     n = 0;
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      if (mesh.get_used_vertices()[v])
        {
          const Point<3> &x = mesh.get_vertices()[v];
          for (unsigned int d = 0; d < 3; ++d)
            {
              lower[d] = n == 0 ? x[d] : std::min(lower[d], x[d]);
              upper[d] = n == 0 ? x[d] : std::max(upper[d], x[d]);
            }
          motions.centre += x;
          ++n;
        }
    motions.centre /= std::max(n, 1u);
    motions.length = std::max(lower.distance(upper), std::numeric_limits<double>::min());

    // M = Σ φᵀφ over all DoFs, P = the same over the prescribed DoFs (6 × 6 each); the free
    // motions are the eigenvectors of M^{-1/2} P M^{-1/2} with eigenvalues below 1e-10 (their
    // norm on the prescribed DoFs is below 1e-5 of their norm).
    FullMatrix<double> M(6, 6), P(6, 6);
    FreeRigidMotions   unit;
    unit.centre       = motions.centre;
    unit.length       = motions.length;
    unit.coefficients = IdentityMatrix(6);
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      {
        if (!mesh.get_used_vertices()[v])
          continue;
        std::array<Tensor<1, 3>, 6> phi;
        for (unsigned int i = 0; i < 6; ++i)
          phi[i] = unit.value(i, mesh.get_vertices()[v]);
        const auto it = prescribed.find(v);
        for (unsigned int c = 0; c < 3; ++c)
          {
            const bool fixed = it != prescribed.end() && it->second[c].has_value();
            for (unsigned int i = 0; i < 6; ++i)
              for (unsigned int j = 0; j < 6; ++j)
                {
                  M(i, j) += phi[i][c] * phi[j][c];
                  if (fixed)
                    P(i, j) += phi[i][c] * phi[j][c];
                }
          }
      }
    std::vector<double> w;
    FullMatrix<double>  V;
    symmetric_eigen(M, w, V);
    FullMatrix<double> M_inverse_root(6, 6); // M^{-1/2}
    for (unsigned int i = 0; i < 6; ++i)
      for (unsigned int j = 0; j < 6; ++j)
        for (unsigned int k = 0; k < 6; ++k)
          M_inverse_root(i, j) += V(i, k) * V(j, k) / std::sqrt(w[k]);
    FullMatrix<double> A(6, 6), tmp(6, 6);
    M_inverse_root.mmult(tmp, P);
    tmp.mmult(A, M_inverse_root);
    symmetric_eigen(A, w, V);
    std::vector<Vector<double>> free;
    for (unsigned int k = 0; k < 6; ++k)
      if (w[k] < 1e-10)
        {
          Vector<double> c(6), u(6);
          for (unsigned int i = 0; i < 6; ++i)
            u[i] = V(i, k);
          M_inverse_root.vmult(c, u);
          for (const auto &f : free) // orthonormal in the coefficients
            c.add(-(c * f), f);
          c /= c.l2_norm();
          free.push_back(c);
        }
    motions.coefficients.reinit(6, free.size());
    for (unsigned int j = 0; j < free.size(); ++j)
      for (unsigned int i = 0; i < 6; ++i)
        motions.coefficients(i, j) = free[j][i];
    return motions;
  }

  Vector<double>
  Body::load_work(const FreeRigidMotions &motions) const
  {
    Vector<double> work(motions.n());
    const auto    &bc = parameters.boundary_conditions;
    // The motions are linear: the integral of a constant load times v_j over a simplex is the
    // load times v_j at its centroid times its measure.
    for (const auto &cell : mesh.active_cell_iterators())
      {
        if (bc.volume_force.norm() > 0)
          for (unsigned int j = 0; j < motions.n(); ++j)
            work[j] += bc.volume_force * motions.value(j, cell->center()) * cell->measure();
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            for (const auto &traction : bc.tractions)
              if (traction.boundary.contains(*face))
                {
                  const double area = 0.5 * cross_product_3d(face->vertex(1) - face->vertex(0),
                                                             face->vertex(2) - face->vertex(0))
                                              .norm();
                  for (unsigned int j = 0; j < motions.n(); ++j)
                    work[j] += traction.value * motions.value(j, face->center()) * area;
                }
      }
    return work;
  }

  void
  Body::check_held() const
  {
    const unsigned int n_free = free_rigid_motions().n();
    require(n_free == 0,
            "Body '" + parameters.name + "' is not held: its prescribed displacements leave " +
              std::to_string(n_free) +
              " rigid body motion(s) free and the scene has no contact, so the linear elastic "
              "problem has no unique solution (equilibrium of the loads is not guaranteed). "
              "Clamp or prescribe displacements on a larger part of its boundary.");
  }

  unsigned int
  Body::n_free_dofs() const
  {
    unsigned int n = 3 * mesh.n_used_vertices();
    for (const auto &[v, value] : prescribed)
      for (const auto &c : value)
        if (c)
          --n;
    return n;
  }
} // namespace FetiContact
