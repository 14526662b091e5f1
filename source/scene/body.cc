#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/mesh_generation.h>
#include <feticontact/subdomain/rigid_body_modes.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <tuple>
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
    create_and_partition(MPI_COMM_SELF);
    set_up_boundary();
  }

  void
  Body::create_and_partition(const MPI_Comm communicator)
  {
    comm              = communicator;
    cells_distributed = Utilities::MPI::n_mpi_processes(comm) > 1;
    const bool root   = Utilities::MPI::this_mpi_process(comm) == 0;
    const auto create = [&]() {
      if (cells_distributed && !root)
        return;
      MeshGeneration::create_mesh(parameters.mesh, mesh, parameters.name);
      partition = partition_cells(mesh, parameters.decomposition, parameters.mesh, parameters.name);
      // Partitioned in the body's own frame (Decomposition/Blocks cut its bounding box there),
      // then moved to the scene.
      if (!parameters.mesh.transform.identity())
        GridTools::transform(parameters.mesh.transform, mesh);
      cells_per_part.assign(partition.n_parts, 0);
      for (const unsigned int p : partition.part_of_cell)
        ++cells_per_part[p];
      n_cells    = mesh.n_active_cells();
      n_vertices = mesh.n_used_vertices();
    };
    if (!cells_distributed)
      {
        create();
        list_cells_of_parts();
        return;
      }
    lattice = LatticeParts::of(parameters);
    if (lattice)
      {
        partition.n_parts = lattice->n_parts();
        cells_per_part.resize(partition.n_parts);
        for (unsigned int p = 0; p < partition.n_parts; ++p)
          cells_per_part[p] = lattice->n_cells(p);
        n_cells    = lattice->n_cells();
        n_vertices = lattice->n_vertices();
        return;
      }
    MPITools::collectively<InputError>(comm, create);
    cells_per_part    = Utilities::MPI::broadcast(comm, cells_per_part, 0);
    partition.n_parts = cells_per_part.size();
    n_cells           = Utilities::MPI::broadcast(comm, n_cells, 0);
    n_vertices        = Utilities::MPI::broadcast(comm, n_vertices, 0);
  }

  void
  Body::distribute(const std::function<unsigned int(unsigned int)> &owner)
  {
    if (!cells_distributed)
      return;
    part_owner.resize(partition.n_parts);
    for (unsigned int p = 0; p < partition.n_parts; ++p)
      part_owner[p] = owner(p);
    const unsigned int     rank = Utilities::MPI::this_mpi_process(comm);
    std::vector<PartCells> own;
    if (lattice)
      for (unsigned int p = 0; p < partition.n_parts; ++p)
        {
          if (part_owner[p] == rank)
            own.push_back(lattice->part_cells(p));
        }
    else
      {
        // Rank 0 cuts every part from the whole mesh and sends it to its owner.
        std::map<unsigned int, std::vector<PartCells>> outgoing;
        if (rank == 0)
          {
            list_cells_of_parts();
            const auto parts = parts_of_vertices(mesh, partition);
            for (unsigned int p = 0; p < partition.n_parts; ++p)
              outgoing[part_owner[p]].push_back(part_cells(p, parts));
            mesh.clear();
          }
        for (auto &[from, list] : Utilities::MPI::some_to_some(comm, outgoing))
          for (auto &part : list)
            own.push_back(std::move(part));
        std::sort(own.begin(), own.end(), [](const PartCells &a, const PartCells &b) {
          return a.part < b.part;
        });
      }
    hold(own);
  }

  void
  Body::hold(const std::vector<PartCells> &own)
  {
    // This rank's mesh: the cells of its parts in the order of the body's cells, their vertices
    // merged by their numbers in the body; faces on the body's boundary keep their ids, the
    // others that bound this rank's cells become interface faces.
    std::vector<std::tuple<unsigned int, const PartCells *, unsigned int>> cells; // (cell, part, i)
    for (const auto &part : own)
      for (unsigned int c = 0; c < part.cells.size(); ++c)
        cells.emplace_back(part.body_cell[c], &part, c);
    std::sort(cells.begin(), cells.end());
    std::unordered_map<unsigned int, unsigned int> local_vertex;
    std::vector<Point<3>>                          points;
    std::vector<CellData<3>>                       cell_data;
    std::vector<unsigned int>                      part_of_cell;
    vertex_number.clear();
    cell_number.clear();
    holder_start.assign(1, 0);
    holder_parts.clear();
    for (const auto &[body_cell, part, c] : cells)
      {
        CellData<3> data(4);
        for (unsigned int v = 0; v < 4; ++v)
          {
            const unsigned int w = part->cells[c][v];
            const auto [entry, first_seen] =
              local_vertex.emplace(part->body_vertex[w], points.size());
            if (first_seen)
              {
                points.push_back(part->points[w]);
                vertex_number.push_back(part->body_vertex[w]);
                const auto holders = part->holders(w);
                holder_parts.insert(holder_parts.end(), holders.begin(), holders.end());
                holder_start.push_back(holder_parts.size());
              }
            data.vertices[v] = entry->second;
          }
        data.material_id = index;
        cell_data.push_back(data);
        cell_number.push_back(body_cell);
        part_of_cell.push_back(part->part);
      }
    std::map<std::array<unsigned int, 3>, types::boundary_id> boundary_faces;
    for (const auto &part : own)
      for (const auto &[face, id] : part.boundary_faces)
        {
          std::array<unsigned int, 3> key;
          for (unsigned int v = 0; v < 3; ++v)
            key[v] = part.body_vertex[face[v]];
          std::sort(key.begin(), key.end());
          boundary_faces[key] = id;
        }
    mesh.clear();
    if (!cell_data.empty()) // (a rank may own no part of this body)
      mesh.create_triangulation(points, cell_data, SubCellData());
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            std::array<unsigned int, 3> key;
            for (unsigned int v = 0; v < 3; ++v)
              key[v] = vertex_number[face->vertex_index(v)];
            std::sort(key.begin(), key.end());
            const auto it = boundary_faces.find(key);
            face->set_boundary_id(it == boundary_faces.end() ? interface_boundary_id : it->second);
          }
    partition.part_of_cell = std::move(part_of_cell);
    list_cells_of_parts();
  }

  void
  Body::list_cells_of_parts()
  {
    cells_of_part.assign(partition.n_parts, {});
    for (const auto &cell : mesh.active_cell_iterators())
      cells_of_part[partition.part_of_cell[cell->active_cell_index()]].push_back(cell);
  }

  void
  Body::set_up_boundary()
  {
    auto &bc = parameters.boundary_conditions;
    for (auto &p : bc.prescribed_displacements)
      p.boundary.resolve(mesh, parameters.name, mesh_comm(), parameters.mesh.transform);
    for (auto &t : bc.tractions)
      t.boundary.resolve(mesh, parameters.name, mesh_comm(), parameters.mesh.transform);
    collect_prescribed();
  }

  namespace
  {
    /**
     * One vertex's Γ_u as the boundary parts prescribe it: per component the value and the
     * index of the prescription (the last in the parameter file wins among those that agree).
     */
    struct VertexPrescription
    {
      std::array<double, 3>       value{};
      std::array<unsigned int, 3> source{{numbers::invalid_unsigned_int,
                                          numbers::invalid_unsigned_int,
                                          numbers::invalid_unsigned_int}};

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &value &source;
      }
    };

    /**
     * Adds component @p c = @p value of prescription @p p to @p target; two prescriptions that
     * differ there contradict each other.
     */
    void
    add_prescription(VertexPrescription                                    &target,
                     const unsigned int                                     c,
                     const double                                           value,
                     const unsigned int                                     p,
                     const std::vector<Parameters::PrescribedDisplacement> &list,
                     const std::string                                     &body_name)
    {
      if (target.source[c] != numbers::invalid_unsigned_int && target.source[c] != p)
        {
          const double a = target.value[c], b = value;
          require(std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)),
                  "Body '" + body_name + "': the boundary parts <" +
                    list[std::min(p, target.source[c])].boundary.name() + "> and <" +
                    list[std::max(p, target.source[c])].boundary.name() +
                    "> prescribe different displacements (" +
                    InputParsing::number_text(p < target.source[c] ? b : a) + " and " +
                    InputParsing::number_text(p < target.source[c] ? a : b) + ") for component " +
                    std::to_string(c) + " at the vertex they share.");
          if (p < target.source[c])
            return;
        }
      target.value[c]  = value;
      target.source[c] = p;
    }
  } // namespace

  void
  Body::collect_prescribed()
  {
    // Γ_u vertex by vertex from the boundary faces of this rank's mesh; two parts that prescribe
    // different values for the same component of a vertex contradict each other.
    const auto &list = parameters.boundary_conditions.prescribed_displacements;
    std::map<unsigned int, VertexPrescription> found; // by body vertex
    MPITools::collectively<InputError>(mesh_comm(), [&]() {
      for (const auto &cell : mesh.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            for (unsigned int p = 0; p < list.size(); ++p)
              if (list[p].boundary.contains(*face))
                for (const unsigned int v : face->vertex_indices())
                  for (unsigned int c = 0; c < 3; ++c)
                    if (list[p].value[c])
                      add_prescription(found[body_vertex(face->vertex_index(v))],
                                       c,
                                       *list[p].value[c],
                                       p,
                                       list,
                                       parameters.name);
    });
    if (distributed())
      {
        // A vertex on an interface between ranks: its holders on other ranks may see boundary
        // faces at it that this rank does not. Every rank sends what it found at such a vertex
        // to the owners of the vertex's other parts.
        std::map<unsigned int, std::vector<std::pair<unsigned int, VertexPrescription>>> outgoing;
        for (unsigned int v = 0; v + 1 < holder_start.size(); ++v)
          {
            const auto it = found.find(vertex_number[v]);
            if (it == found.end())
              continue;
            std::set<unsigned int> ranks;
            for (unsigned int h = holder_start[v]; h < holder_start[v + 1]; ++h)
              if (!holds_part(holder_parts[h]))
                ranks.insert(part_owner[holder_parts[h]]);
            for (const unsigned int r : ranks)
              outgoing[r].push_back(*it);
          }
        const auto incoming = Utilities::MPI::some_to_some(comm, outgoing);
        MPITools::collectively<InputError>(comm, [&]() {
          for (const auto &[from, list_from] : incoming)
            for (const auto &[vertex, prescription] : list_from)
              for (unsigned int c = 0; c < 3; ++c)
                if (prescription.source[c] != numbers::invalid_unsigned_int)
                  add_prescription(found[vertex],
                                   c,
                                   prescription.value[c],
                                   prescription.source[c],
                                   list,
                                   parameters.name);
        });
      }
    prescribed.clear();
    for (const auto &[vertex, prescription] : found)
      {
        Prescribed &value = prescribed[vertex];
        for (unsigned int c = 0; c < 3; ++c)
          if (prescription.source[c] != numbers::invalid_unsigned_int)
            value[c] = prescription.value[c];
      }
  }

  std::vector<std::vector<unsigned int>>
  Body::parts_of_mesh_vertices() const
  {
    if (!distributed())
      return parts_of_vertices(mesh, partition);
    std::vector<std::vector<unsigned int>> parts(mesh.n_vertices());
    for (unsigned int v = 0; v < parts.size(); ++v)
      parts[v].assign(holder_parts.begin() + holder_start[v],
                      holder_parts.begin() + holder_start[v + 1]);
    return parts;
  }

  std::vector<unsigned int>
  Body::reported_vertices() const
  {
    std::vector<unsigned int> reported;
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      if (distributed() ? holds_part(holder_parts[holder_start[v]]) : mesh.get_used_vertices()[v])
        reported.push_back(v);
    return reported;
  }

  PartCells
  Body::part_cells(const unsigned int part) const
  {
    return part_cells(part, parts_of_mesh_vertices());
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
            const unsigned int mesh_vertex = cell->vertex_index(v);
            const auto [entry, first_seen] =
              local_vertex.emplace(mesh_vertex, result.points.size());
            if (first_seen)
              {
                result.add_vertex(cell->vertex(v),
                                  body_vertex(mesh_vertex),
                                  parts_of_vertex[mesh_vertex]);
              }
            local[v] = entry->second;
          }
        result.cells.push_back(local);
        result.body_cell.push_back(body_cell(cell->active_cell_index()));
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() != interface_boundary_id)
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

  std::string
  FreeRigidMotions::text() const
  {
    // Rounded to the decimal place of 1e-3 of @p unit (directions: of 1; points: of the size).
    const auto rounded = [](const Tensor<1, 3> &v, const double unit) {
      const double place  = std::pow(10.0, std::floor(std::log10(1e-3 * unit)));
      const auto   number = [&](const double x) {
        const double r = std::round(x / place) * place;
        return InputParsing::number_text(std::abs(r) < place ? 0.0 : r);
      };
      return "(" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + ")";
    };
    // A direction with its largest component positive.
    const auto canonical = [](const Tensor<1, 3> &v) {
      unsigned int largest = 0;
      for (unsigned int k = 1; k < 3; ++k)
        if (std::abs(v[k]) > std::abs(v[largest]) + 1e-12)
          largest = k;
      return v[largest] < 0 ? -v : v;
    };
    // The motions are v(x) = t + ω × (x − c)/L. The combinations of the columns without
    // rotation (the kernel of Ω = their ω's) are the free translations; the others, with their
    // translation part orthogonal to the free translations, are rotations about an axis.
    const unsigned int r = n();
    if (r == 0)
      return "";
    LAPACKFullMatrix<double> OtO(r, r);
    for (unsigned int i = 0; i < r; ++i)
      for (unsigned int j = 0; j < r; ++j)
        for (unsigned int k = 3; k < 6; ++k)
          OtO(i, j) += coefficients(k, i) * coefficients(k, j);
    Vector<double>     weights;
    FullMatrix<double> combinations;
    OtO.compute_eigenvalues_symmetric(-1.0, 2.0 * r + 1.0, 1e-14, weights, combinations);
    const auto motion = [&](const unsigned int j, Tensor<1, 3> &t, Tensor<1, 3> &omega) {
      t = omega = Tensor<1, 3>();
      for (unsigned int i = 0; i < r; ++i)
        for (unsigned int k = 0; k < 3; ++k)
          {
            t[k] += coefficients(k, i) * combinations(i, j);
            omega[k] += coefficients(k + 3, i) * combinations(i, j);
          }
    };
    std::vector<Tensor<1, 3>> translations; // orthonormal
    std::vector<std::string>  rotations;
    for (unsigned int j = 0; j < weights.size(); ++j)
      if (weights[j] < 1e-10)
        {
          Tensor<1, 3> t, omega;
          motion(j, t, omega);
          for (const auto &e : translations)
            t -= (t * e) * e;
          if (t.norm() > 1e-8)
            translations.push_back(t / t.norm());
        }
    for (unsigned int j = 0; j < weights.size(); ++j)
      if (weights[j] >= 1e-10)
        {
          Tensor<1, 3> t, omega;
          motion(j, t, omega);
          for (const auto &e : translations)
            t -= (t * e) * e;
          const Tensor<1, 3> axis = canonical(omega / omega.norm());
          const Point<3>     through =
            centre + length * cross_product_3d(omega, t) / omega.norm_square();
          rotations.push_back(
            "rotation about " + rounded(axis, 1) + " through " + rounded(through, length) +
            (std::abs(t * axis) > 1e-6 * omega.norm() ? " with a translation along it" : ""));
        }
    std::string text;
    if (translations.size() == 3)
      text = "translations in every direction";
    else if (translations.size() == 2)
      text = "translations normal to " +
             rounded(canonical(cross_product_3d(translations[0], translations[1])), 1);
    else if (translations.size() == 1)
      text = "translation along " + rounded(canonical(translations[0]), 1);
    for (const auto &rotation : rotations)
      text += (text.empty() ? "" : "; ") + rotation;
    return text;
  }

  FreeRigidMotions
  Body::free_rigid_motions() const
  {
    // Every vertex of the body once, by the rank that reports it. The sums are exact
    // (ExactSum), so that the motions are the same bits however the cells are distributed.
    FreeRigidMotions      motions;
    const auto            reported = reported_vertices();
    const double          inf      = std::numeric_limits<double>::infinity();
    Point<3>              lower(inf, inf, inf), upper(-inf, -inf, -inf);
    std::vector<ExactSum> centre(3);
    for (const unsigned int v : reported)
      {
        const Point<3> &x = mesh.get_vertices()[v];
        for (unsigned int d = 0; d < 3; ++d)
          {
            lower[d] = std::min(lower[d], x[d]);
            upper[d] = std::max(upper[d], x[d]);
            centre[d].add(x[d]);
          }
      }
    const MPI_Comm     mc = mesh_comm();
    const unsigned int n  = Utilities::MPI::sum<unsigned int>(reported.size(), mc);
    ExactSum::sum_over_ranks(centre, mc);
    for (unsigned int d = 0; d < 3; ++d)
      {
        motions.centre[d] = centre[d].value();
        lower[d]          = Utilities::MPI::min(lower[d], mc);
        upper[d]          = Utilities::MPI::max(upper[d], mc);
      }
    motions.centre /= std::max(n, 1u);
    motions.length =
      std::max(n > 0 ? lower.distance(upper) : 0., std::numeric_limits<double>::min());

    // M = Σ φᵀφ over all DoFs, P = the same over the prescribed DoFs (6 × 6 each); the free
    // motions are the eigenvectors of M^{-1/2} P M^{-1/2} with eigenvalues below 1e-10 (their
    // norm on the prescribed DoFs is below 1e-5 of their norm).
    FullMatrix<double> M(6, 6), P(6, 6);
    FreeRigidMotions   unit;
    unit.centre       = motions.centre;
    unit.length       = motions.length;
    unit.coefficients = IdentityMatrix(6);
    std::vector<ExactSum> entries(2 * 36); // M, then P
    for (const unsigned int v : reported)
      {
        std::array<Tensor<1, 3>, 6> phi;
        for (unsigned int i = 0; i < 6; ++i)
          phi[i] = unit.value(i, mesh.get_vertices()[v]);
        const auto it = prescribed.find(body_vertex(v));
        for (unsigned int c = 0; c < 3; ++c)
          {
            const bool fixed = it != prescribed.end() && it->second[c].has_value();
            for (unsigned int i = 0; i < 6; ++i)
              for (unsigned int j = i; j < 6; ++j)
                {
                  entries[6 * i + j].add(phi[i][c] * phi[j][c]);
                  if (fixed)
                    entries[36 + 6 * i + j].add(phi[i][c] * phi[j][c]);
                }
          }
      }
    ExactSum::sum_over_ranks(entries, mc);
    for (unsigned int i = 0; i < 6; ++i)
      for (unsigned int j = i; j < 6; ++j)
        {
          M(i, j) = M(j, i) = entries[6 * i + j].value();
          P(i, j) = P(j, i) = entries[36 + 6 * i + j].value();
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
    // Exact sums (ExactSum): the same bits however the cells are distributed.
    std::vector<ExactSum> work(motions.n());
    const auto           &bc = parameters.boundary_conditions;
    // The motions are linear: the integral of a constant load times v_j over a simplex is the
    // load times v_j at its centroid times its measure.
    for (const auto &cell : mesh.active_cell_iterators())
      {
        if (bc.volume_force.norm() > 0)
          for (unsigned int j = 0; j < motions.n(); ++j)
            work[j].add(bc.volume_force * motions.value(j, cell->center()) * cell->measure());
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            for (const auto &traction : bc.tractions)
              if (traction.boundary.contains(*face))
                {
                  const double area = 0.5 * cross_product_3d(face->vertex(1) - face->vertex(0),
                                                             face->vertex(2) - face->vertex(0))
                                              .norm();
                  for (unsigned int j = 0; j < motions.n(); ++j)
                    work[j].add(traction.value * motions.value(j, face->center()) * area);
                }
      }
    ExactSum::sum_over_ranks(work, mesh_comm());
    Vector<double> total(motions.n());
    for (unsigned int j = 0; j < motions.n(); ++j)
      total[j] = work[j].value();
    return total;
  }

  void
  Body::check_held() const
  {
    const FreeRigidMotions free = free_rigid_motions();
    if (free.n() > 0)
      throw InputError(
        "Body '" + parameters.name + "' is not held: its prescribed displacements leave " +
        std::to_string(free.n()) + " rigid body motion(s) free (" + free.text() +
        ") and no contact zone holds it, so the linear elastic problem has no unique "
        "solution (equilibrium of the loads is not guaranteed). Clamp or prescribe "
        "displacements on a larger part of its boundary, or add a contact zone.");
  }

  unsigned int
  Body::n_free_dofs() const
  {
    unsigned int n = 0;
    for (const unsigned int v : reported_vertices())
      {
        const auto it = prescribed.find(body_vertex(v));
        for (unsigned int c = 0; c < 3; ++c)
          n += it == prescribed.end() || !it->second[c];
      }
    return Utilities::MPI::sum(n, mesh_comm());
  }
} // namespace FetiContact
