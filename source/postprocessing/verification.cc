#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/subdomain_threads.h>
#include <feticontact/local_solvers/cholmod_solver.h>
#include <feticontact/postprocessing/verification.h>
#include <feticontact/subdomain/elasticity_assembly.h>

#include <algorithm>
#include <boost/serialization/array.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace FetiContact
{
  using namespace dealii;

  std::vector<std::vector<Tensor<1, 3>>>
  gather_vertex_displacements(const MPI_Comm                            comm,
                              const std::vector<std::unique_ptr<Body>> &bodies,
                              const std::vector<Subdomain *>           &owned,
                              const std::vector<Vector<double>>        &u)
  {
    // Vertices by their numbers in the body's whole mesh (a rank's mesh may hold some cells only).
    std::vector<std::vector<Tensor<1, 3>>> result(bodies.size());
    std::vector<unsigned int>              n_vertices(bodies.size(), 0);
    for (const Subdomain *s : owned)
      for (const auto &[w, v] : s->reported_vertices())
        n_vertices[s->body.index] = std::max(n_vertices[s->body.index], w + 1);
    Utilities::MPI::max(n_vertices, comm, n_vertices);
    for (const auto &body : bodies)
      result[body->index].resize(n_vertices[body->index]);
    for (unsigned int i = 0; i < owned.size(); ++i)
      for (const auto &[w, v] : owned[i]->reported_vertices())
        for (unsigned int c = 0; c < 3; ++c)
          result[owned[i]->body.index][w][c] = u[i][owned[i]->vertex_dofs[v][c]];
    for (auto &r : result)
      {
        double *const values = reinterpret_cast<double *>(r.data());
        Utilities::MPI::sum(ArrayView<const double>(values, 3 * r.size()),
                            comm,
                            ArrayView<double>(values, 3 * r.size()));
      }
    return result;
  }

  std::vector<Tensor<1, 3>>
  solve_monolithic(const Body &body, const Mapping<3> &mapping, const FiniteElement<3> &fe)
  {
    DoFHandler<3> dof_handler(body.mesh);
    dof_handler.distribute_dofs(fe);
    SparsityPattern      sparsity;
    SparseMatrix<double> K;
    Vector<double>       f;
    assemble_elasticity(dof_handler, mapping, body.parameters, sparsity, K, f);
    const auto                         vertex_dofs = vertex_dof_indices(dof_handler);
    std::vector<std::optional<double>> prescribed(dof_handler.n_dofs());
    for (const auto &[v, value] : body.prescribed)
      for (unsigned int c = 0; c < 3; ++c)
        prescribed[vertex_dofs[v][c]] = value[c];
    eliminate_prescribed_dofs(prescribed, K, f);
    // The whole body: the 64-bit interface (the brick's factor at 10⁶ unknowns does not fit the
    // 32-bit one of the subdomains' solver).
    solve_by_long_cholmod(K, f);
    std::vector<Tensor<1, 3>> u(body.mesh.n_vertices());
    for (unsigned int v = 0; v < u.size(); ++v)
      if (vertex_dofs[v][0] != numbers::invalid_dof_index)
        for (unsigned int c = 0; c < 3; ++c)
          u[v][c] = f[vertex_dofs[v][c]];
    return u;
  }

  namespace
  {
    /** Per subdomain: the sums of compute_force_balance() before they are added up. */
    struct SubdomainForces
    {
      std::array<double, 3> applied{}, support{};
      /** Σ |f_d|, Σ_{Γ_u} |(K u − f)_d| and Σ_{Γ_u} (|K| |u| + |f|)_d. */
      double applied_magnitudes = 0, support_magnitudes = 0, support_terms = 0;
    };

    SubdomainForces
    forces_of_subdomain(const Subdomain &s, const Vector<double> &u, const Mapping<3> &mapping)
    {
      SparsityPattern      sparsity;
      SparseMatrix<double> K;
      Vector<double>       f, r(s.dof_handler.n_dofs());
      SubdomainForces      local;
      assemble_elasticity(s.dof_handler, mapping, s.body.parameters, sparsity, K, f);
      K.vmult(r, u);
      r -= f;
      for (unsigned int d = 0; d < f.size(); ++d)
        {
          const unsigned int c = s.dof_component[d];
          local.applied[c] += f[d];
          local.applied_magnitudes += std::abs(f[d]);
          if (!s.prescribed[d])
            continue;
          local.support[c] += r[d];
          local.support_magnitudes += std::abs(r[d]);
          double terms = std::abs(f[d]);
          for (auto entry = K.begin(d); entry != K.end(d); ++entry)
            terms += std::abs(entry->value() * u[entry->column()]);
          local.support_terms += terms;
        }
      return local;
    }
  } // namespace

  std::vector<ForceBalance>
  compute_force_balance(const MPI_Comm                         comm,
                        const unsigned int                     n_bodies,
                        const std::vector<Subdomain *>        &owned,
                        const std::vector<Vector<double>>     &u,
                        const Mapping<3>                      &mapping,
                        const std::vector<ContactForceOnBody> &contact_forces)
  {
    // Per subdomain (on the subdomain threads) the applied forces f and the support forces
    // K u − f on the prescribed DoFs, then added in the order of the subdomains.
    std::vector<SubdomainForces> of_subdomain(owned.size());
    SubdomainThreads::for_each(owned.size(), [&](const unsigned int i) {
      of_subdomain[i] = forces_of_subdomain(*owned[i], u[i], mapping);
    });
    // The subdomains' sums added exactly: the same bits on any number of ranks.
    constexpr unsigned int per_body = 9;
    std::vector<ExactSum>  exact(per_body * n_bodies);
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const SubdomainForces &local = of_subdomain[i];
        const auto             sums  = exact.begin() + per_body * owned[i]->body.index;
        for (unsigned int c = 0; c < 3; ++c)
          {
            sums[c].add(local.applied[c]);
            sums[3 + c].add(local.support[c]);
          }
        sums[6].add(local.applied_magnitudes);
        sums[7].add(local.support_magnitudes);
        sums[8].add(local.support_terms);
      }
    ExactSum::sum_over_ranks(exact, comm);
    std::vector<ForceBalance> balance(n_bodies);
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        ForceBalance &fb   = balance[b];
        const auto    sums = exact.begin() + per_body * b;
        for (unsigned int c = 0; c < 3; ++c)
          {
            fb.applied[c] = sums[c].value();
            fb.support[c] = sums[3 + c].value();
          }
        double contact_magnitudes = 0;
        if (b < contact_forces.size())
          {
            fb.contact         = contact_forces[b].force;
            contact_magnitudes = contact_forces[b].magnitudes;
          }
        // The forces that pass through the body; for a body that moves without strain (all
        // of them rounding), √ε times the terms of K u − f whose sum is its support force,
        // the accuracy that sum can have.
        fb.through = sums[6].value() + sums[7].value() + contact_magnitudes;
        const double attainable =
          std::sqrt(std::numeric_limits<double>::epsilon()) * sums[8].value();
        const double scale = std::max(fb.through, attainable);
        fb.relative_imbalance =
          scale > 0 ? (fb.applied + fb.support + fb.contact).norm() / scale : 0.0;
      }
    return balance;
  }

  VertexDisplacements
  read_reference_displacements(const std::string                        &file,
                               const std::vector<std::unique_ptr<Body>> &bodies)
  {
    require(!std::filesystem::is_directory(file),
            "Verification/Reference displacements: '" + file + "' is a folder, not a file.");
    std::ifstream in(file);
    require(in.good(), "Cannot open the reference displacements '" + file + "'.");
    std::string line;
    require(static_cast<bool>(std::getline(in, line)),
            "The reference displacements '" + file + "' are empty.");
    const auto split = [](const std::string &text) {
      std::vector<std::string> fields;
      std::stringstream        stream(text);
      std::string              field;
      while (std::getline(stream, field, ','))
        fields.push_back(InputParsing::trim(field));
      return fields;
    };
    const auto header = split(line);
    const auto column = [&](const std::string &name) -> int {
      const auto it = std::find(header.begin(), header.end(), name);
      return it == header.end() ? -1 : int(it - header.begin());
    };
    const int          body_column = column("body");
    std::array<int, 6> columns{
      {column("x"), column("y"), column("z"), column("ux"), column("uy"), column("uz")}};
    require(std::all_of(columns.begin(), columns.end(), [](int c) { return c >= 0; }),
            "The reference displacements '" + file +
              "' need the columns x, y, z, ux, uy, uz (and body with several bodies).");
    require(body_column >= 0 || bodies.size() == 1,
            "The reference displacements '" + file +
              "' have no column 'body', but the scene has several bodies.");

    // Rows by body and by position, rounded to 1e-9 of the body's size.
    std::vector<double> unit(bodies.size());
    for (const auto &body : bodies)
      {
        double size = 0;
        for (const auto &x : body->mesh.get_vertices())
          size = std::max(size, x.norm());
        unit[body->index] = 1e-9 * std::max(Utilities::MPI::max(size, body->mesh_comm()), 1e-300);
      }
    using Key      = std::array<long long, 3>;
    const auto key = [&](const unsigned int b, const Point<3> &x) {
      return Key{
        {std::llround(x[0] / unit[b]), std::llround(x[1] / unit[b]), std::llround(x[2] / unit[b])}};
    };
    std::vector<std::map<Key, Tensor<1, 3>>> rows(bodies.size());
    unsigned int                             line_number = 1;
    while (std::getline(in, line))
      {
        ++line_number;
        if (InputParsing::trim(line).empty())
          continue;
        const auto fields = split(line);
        const auto where  = "line " + std::to_string(line_number) + " of '" + file + "'";
        try
          {
            // Bodies are numbered from 1, as the parameter file counts them.
            const long number = body_column >= 0 ? std::stol(fields.at(body_column)) : 1;
            require(number >= 1 && number <= long(bodies.size()),
                    where + ": no body " + std::to_string(number) + " (the scene has bodies 1 to " +
                      std::to_string(bodies.size()) + ").");
            const unsigned int b = number - 1;
            Point<3>           x;
            Tensor<1, 3>       u;
            for (unsigned int d = 0; d < 3; ++d)
              {
                x[d] = std::stod(fields.at(columns[d]));
                u[d] = std::stod(fields.at(columns[3 + d]));
              }
            require(std::isfinite(x.norm()) && std::isfinite(u.norm()),
                    where + ": a value is not finite.");
            rows[b][key(b, x)] = u;
          }
        catch (const InputError &)
          {
            throw;
          }
        catch (const std::exception &)
          {
            throw InputError(where + ": not a row of numbers (body, x, y, z, ux, uy, uz).");
          }
      }

    VertexDisplacements reference(bodies.size());
    for (const auto &body : bodies)
      MPITools::collectively<InputError>(body->mesh_comm(), [&]() {
        for (unsigned int v = 0; v < body->mesh.n_vertices(); ++v)
          if (body->mesh.get_used_vertices()[v])
            {
              const auto &x  = body->mesh.get_vertices()[v];
              const auto  it = rows[body->index].find(key(body->index, x));
              if (it == rows[body->index].end())
                {
                  std::ostringstream point;
                  point << x;
                  throw InputError("The reference displacements '" + file +
                                   "' have no row for the vertex (" + point.str() + ") of body '" +
                                   body->parameters.name +
                                   "': they were written for another mesh.");
                }
              reference.set(body->index, body->body_vertex(v), it->second);
            }
      });
    return reference;
  }

  ReferenceDifference
  compare_with_reference(const MPI_Comm                     comm,
                         const std::vector<Subdomain *>    &owned,
                         const Mapping<3>                  &mapping,
                         const std::vector<Vector<double>> &u,
                         const VertexDisplacements         &reference)
  {
    ReferenceDifference result;
    double              max_difference = 0, max_reference = 0;
    for (unsigned int i = 0; i < owned.size(); ++i)
      for (const auto &[w, v] : owned[i]->reported_vertices())
        {
          const Tensor<1, 3> &r = reference(owned[i]->body.index, w);
          Tensor<1, 3>        e;
          for (unsigned int c = 0; c < 3; ++c)
            e[c] = u[i][owned[i]->vertex_dofs[v][c]] - r[c];
          max_difference = std::max(max_difference, e.norm());
          max_reference  = std::max(max_reference, r.norm());
          ++result.n_vertices;
        }
    max_difference      = Utilities::MPI::max(max_difference, comm);
    max_reference       = Utilities::MPI::max(max_reference, comm);
    result.n_vertices   = Utilities::MPI::sum(result.n_vertices, comm);
    result.max_relative = max_reference > 0 ? max_difference / max_reference : max_difference;

    // Energies Σ_s eᵀK_s e of the difference and of the reference, e interpolated at the DoFs.
    double energies[2] = {0, 0};
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const Subdomain     *s = owned[i];
        SparsityPattern      sparsity;
        SparseMatrix<double> K;
        Vector<double>       f;
        assemble_elasticity(s->dof_handler, mapping, s->body.parameters, sparsity, K, f);
        const unsigned int n = s->dof_handler.n_dofs();
        Vector<double>     e(n), r(n);
        for (unsigned int d = 0; d < n; ++d)
          {
            const unsigned int v = s->body_vertex[s->dof_vertex[d]];
            const unsigned int c = s->dof_component[d];
            r[d]                 = reference(s->body.index, v)[c];
            e[d]                 = u[i][d] - r[d];
          }
        energies[0] += K.matrix_norm_square(e);
        energies[1] += K.matrix_norm_square(r);
      }
    Utilities::MPI::sum(ArrayView<const double>(energies, 2), comm, ArrayView<double>(energies, 2));
    result.energy_relative = energies[1] > 0 ? std::sqrt(std::max(energies[0], 0.) / energies[1]) :
                                               std::sqrt(std::max(energies[0], 0.));
    return result;
  }

  VertexDisplacements
  fetch_vertex_displacements(const MPI_Comm                                  comm,
                             const std::vector<unsigned int>                &first_subdomain,
                             const std::vector<unsigned int>                &owner,
                             const std::vector<Subdomain *>                 &owned,
                             const std::vector<Vector<double>>              &u,
                             const std::vector<std::array<unsigned int, 3>> &wanted)
  {
    const unsigned int n_bodies = first_subdomain.size() - 1;
    // The questions, by the rank that answers them: (body, body vertex, subdomain).
    std::map<unsigned int, std::vector<std::array<unsigned int, 3>>> questions;
    for (const auto &[body, vertex, part] : wanted)
      {
        const unsigned int s = first_subdomain[body] + part;
        questions[owner[s]].push_back({{body, vertex, s}});
      }
    for (auto &[rank, list] : questions)
      {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
      }
    std::map<unsigned int, unsigned int> index_of; // subdomain → index in owned
    for (unsigned int i = 0; i < owned.size(); ++i)
      index_of[owned[i]->global_index] = i;
    std::vector<std::unordered_map<unsigned int, unsigned int>> own_vertex(owned.size());
    const auto answer = [&](const std::vector<std::array<unsigned int, 3>> &asked) {
      std::vector<double> values;
      for (const auto &[body, vertex, s] : asked)
        {
          const unsigned int i = index_of.at(s);
          if (own_vertex[i].empty())
            for (const auto &[w, v] : owned[i]->reported_vertices())
              own_vertex[i][w] = v;
          const unsigned int v = own_vertex[i].at(vertex);
          for (unsigned int c = 0; c < 3; ++c)
            values.push_back(u[i][owned[i]->vertex_dofs[v][c]]);
        }
      return values;
    };
    std::map<unsigned int, std::vector<double>> replies;
    for (const auto &[from, asked] : Utilities::MPI::some_to_some(comm, questions))
      replies[from] = answer(asked);
    const auto          answers = Utilities::MPI::some_to_some(comm, replies);
    VertexDisplacements result(n_bodies);
    for (const auto &[rank, values] : answers)
      {
        const auto &asked = questions.at(rank);
        for (unsigned int k = 0; k < asked.size(); ++k)
          result.set(asked[k][0],
                     asked[k][1],
                     Tensor<1, 3>({values[3 * k], values[3 * k + 1], values[3 * k + 2]}));
      }
    return result;
  }
} // namespace FetiContact
