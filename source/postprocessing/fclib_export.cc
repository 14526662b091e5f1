#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <feticontact/postprocessing/fclib_export.h>
#include <feticontact/subdomain/elasticity_assembly.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#ifdef FETICONTACT_WITH_FCLIB
// fclib.h declares its C functions without extern "C".
extern "C"
{
#  include <fclib.h>
}
#  include <hdf5.h>
#endif

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** The free DoFs of one body: global index in v per vertex and component, or −1. */
    struct BodyDofs
    {
      std::vector<std::array<int, 3>> free_index;
    };

    /** Divides every entry of @p x by @p scale. */
    void
    divide(std::vector<double> &x, const double scale)
    {
      for (double &value : x)
        value /= scale;
    }

#ifdef FETICONTACT_WITH_FCLIB
    /**
     * Writes the scalar attribute @p name of the root group of the HDF5 file @p file, open for
     * writing: a double, or a fixed-length string. Throws std::runtime_error if HDF5 fails.
     */
    template <typename T>
    void
    write_root_attribute(const hid_t file, const std::string &name, const T &value)
    {
      hid_t type;
      if constexpr (std::is_same_v<T, std::string>)
        {
          type = H5Tcopy(H5T_C_S1);
          H5Tset_size(type, value.size() + 1); // with the terminating null
        }
      else
        type = H5Tcopy(H5T_NATIVE_DOUBLE);
      const hid_t space     = H5Screate(H5S_SCALAR);
      const hid_t attribute = H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
      herr_t      status    = -1;
      if (attribute >= 0)
        {
          if constexpr (std::is_same_v<T, std::string>)
            status = H5Awrite(attribute, type, value.c_str());
          else
            status = H5Awrite(attribute, type, &value);
          H5Aclose(attribute);
        }
      H5Sclose(space);
      H5Tclose(type);
      if (status < 0)
        throw std::runtime_error("FCLIB: HDF5 cannot write the attribute " + name);
    }
#endif
  } // namespace

  FclibScales
  fclib_scales(const std::vector<std::unique_ptr<Body>> &bodies,
               const std::vector<ContactNode>           &nodes,
               const FclibProblem                       &problem)
  {
    Assert(!nodes.empty(), ExcMessage("an FCLIB problem needs contact nodes"));
    Assert(problem.units == Parameters::Output::FclibUnits::SI,
           ExcMessage("the scales are taken from the problem in SI units"));
    FclibScales scales;
    scales.youngs_modulus = 0;
    for (const auto &body : bodies)
      scales.youngs_modulus =
        std::max(scales.youngs_modulus, body->parameters.material.youngs_modulus);
    double area = 0;
    for (const auto &node : nodes)
      area += node.area;
    scales.contact_spacing = std::sqrt(area / nodes.size());
    scales.stiffness       = scales.youngs_modulus * scales.contact_spacing;

    double f_max = 0, w_max = 0;
    for (const double value : problem.f)
      f_max = std::max(f_max, std::abs(value));
    for (const double value : problem.w)
      w_max = std::max(w_max, std::abs(value));
    scales.force = std::max(f_max, scales.stiffness * w_max);
    if (scales.force == 0)
      scales.force = scales.stiffness * scales.contact_spacing;
    scales.length = scales.force / scales.stiffness;
    scales.stress = scales.stiffness / scales.length;
    return scales;
  }

  void
  nondimensionalise(FclibProblem &problem, const FclibScales &scales)
  {
    Assert(problem.units == Parameters::Output::FclibUnits::SI,
           ExcMessage("the problem is nondimensional already"));
    divide(problem.v, scales.length);
    divide(problem.u, scales.length);
    divide(problem.w, scales.length);
    divide(problem.r, scales.force);
    divide(problem.f, scales.force);
    divide(problem.M.value, scales.stiffness);
    problem.units  = Parameters::Output::FclibUnits::nondimensional;
    problem.scales = scales;
  }

  namespace
  {
    /**
     * H and w, one frame [n, t1, t2] per contact node: û_c = −e_c·(u_slave − u_master) (+ d),
     * and the forces r and the friction coefficients μ of the nodes, into @p problem, whose
     * @p n_free free DoFs are numbered by @p body_dofs.
     */
    void
    add_contact_frames(FclibProblem                             &problem,
                       const int                                 n_free,
                       const std::vector<std::unique_ptr<Body>> &bodies,
                       const std::vector<BodyDofs>              &body_dofs,
                       const std::vector<ContactNode>           &nodes,
                       const std::vector<ContactNodeResult>     &results)
    {
      auto &H     = problem.H;
      H.n_rows    = n_free;
      H.n_columns = 3 * nodes.size();
      H.column_start.push_back(0);
      problem.w.assign(3 * nodes.size(), 0.0);
      problem.r.assign(3 * nodes.size(), 0.0);
      problem.mu.resize(nodes.size());
      for (unsigned int k = 0; k < nodes.size(); ++k)
        {
          const auto                               &node = nodes[k];
          const std::array<const Tensor<1, 3> *, 3> frame{{&node.n, &node.t1, &node.t2}};
          problem.mu[k]        = node.friction;
          problem.w[3 * k]     = node.gap;
          problem.r[3 * k]     = results[k].lambda_N;
          problem.r[3 * k + 1] = results[k].lambda_T[0];
          problem.r[3 * k + 2] = results[k].lambda_T[1];
          // (body, vertex, sign) of the slave and of the master.
          std::vector<std::tuple<unsigned int, unsigned int, double>> ends{
            {node.body, node.vertex, -1.0}};
          for (const auto &m : node.master)
            ends.emplace_back(m.body, m.vertex, m.weight);
          for (unsigned int c = 0; c < 3; ++c)
            {
              std::vector<std::pair<int, double>> column;
              for (const auto &[b, vertex, sign] : ends)
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    const double coefficient = sign * (*frame[c])[d];
                    const int    i           = body_dofs[b].free_index[vertex][d];
                    if (i >= 0)
                      {
                        if (coefficient != 0)
                          column.emplace_back(i, coefficient);
                      }
                    else
                      problem.w[3 * k + c] += coefficient * *bodies[b]->prescribed.at(vertex)[d];
                  }
              std::sort(column.begin(), column.end());
              for (const auto &[i, value] : column)
                {
                  H.row.push_back(i);
                  H.value.push_back(value);
                }
              H.column_start.push_back(H.row.size());
            }
        }
    }
  } // namespace

  FclibProblem
  assemble_fclib_problem(const std::vector<std::unique_ptr<Body>>     &bodies,
                         const std::vector<ContactNode>               &nodes,
                         const std::vector<ContactNodeResult>         &results,
                         const std::vector<std::vector<Tensor<1, 3>>> &vertex_u,
                         const Mapping<3>                             &mapping,
                         const FiniteElement<3>                       &fe,
                         const Parameters::Output::FclibUnits          units)
  {
    FclibProblem problem;
    // Rows of M as (column, value), global free numbering; M is symmetric, so its compressed
    // columns are its compressed rows.
    std::vector<std::vector<std::pair<int, double>>> rows;
    std::vector<BodyDofs>                            body_dofs(bodies.size());
    int                                              offset = 0;
    for (const auto &body : bodies)
      {
        DoFHandler<3> dof_handler(body->mesh);
        dof_handler.distribute_dofs(fe);
        SparsityPattern      sparsity;
        SparseMatrix<double> K;
        Vector<double>       f;
        assemble_elasticity(dof_handler, mapping, body->parameters, sparsity, K, f);
        const auto vertex_dofs = vertex_dof_indices(dof_handler);

        // ū per DoF (prescribed components) and the free numbering.
        std::vector<std::optional<double>> prescribed(dof_handler.n_dofs());
        for (const auto &[vertex, value] : body->prescribed)
          for (unsigned int c = 0; c < 3; ++c)
            prescribed[vertex_dofs[vertex][c]] = value[c];
        std::vector<int> free(dof_handler.n_dofs(), -1);
        for (types::global_dof_index d = 0; d < free.size(); ++d)
          if (!prescribed[d])
            free[d] = offset++;
        auto &index = body_dofs[body->index].free_index;
        index.assign(vertex_dofs.size(), {{-1, -1, -1}});
        for (unsigned int v = 0; v < vertex_dofs.size(); ++v)
          if (vertex_dofs[v][0] != numbers::invalid_dof_index)
            for (unsigned int c = 0; c < 3; ++c)
              index[v][c] = free[vertex_dofs[v][c]];

        rows.resize(offset);
        problem.f.resize(offset);
        problem.v.resize(offset);
        for (types::global_dof_index d = 0; d < free.size(); ++d)
          {
            if (free[d] < 0)
              continue;
            double rhs = f[d];
            for (auto entry = K.begin(d); entry != K.end(d); ++entry)
              {
                const auto j = entry->column();
                if (free[j] >= 0)
                  rows[free[d]].emplace_back(free[j], entry->value());
                else
                  rhs -= entry->value() * *prescribed[j];
              }
            problem.f[free[d]] = rhs;
          }
        for (unsigned int v = 0; v < vertex_dofs.size(); ++v)
          for (unsigned int c = 0; c < 3; ++c)
            if (index[v][c] >= 0)
              problem.v[index[v][c]] = vertex_u[body->index][v][c];
      }

    auto &M     = problem.M;
    M.n_rows    = offset;
    M.n_columns = offset;
    M.column_start.push_back(0);
    for (auto &row : rows)
      {
        std::sort(row.begin(), row.end());
        for (const auto &[j, value] : row)
          {
            M.row.push_back(j);
            M.value.push_back(value);
          }
        M.column_start.push_back(M.row.size());
      }

    add_contact_frames(problem, offset, bodies, body_dofs, nodes, results);

    // u = Hᵀ v + w.
    problem.u     = problem.w;
    const auto &H = problem.H;
    for (int j = 0; j < H.n_columns; ++j)
      for (int p = H.column_start[j]; p < H.column_start[j + 1]; ++p)
        problem.u[j] += H.value[p] * problem.v[H.row[p]];

    if (units == Parameters::Output::FclibUnits::nondimensional)
      nondimensionalise(problem, fclib_scales(bodies, nodes, problem));
    return problem;
  }

  bool
  fclib_available()
  {
#ifdef FETICONTACT_WITH_FCLIB
    return true;
#else
    return false;
#endif
  }

  void
  write_fclib(const std::string  &file,
              const FclibProblem &problem,
              const std::string  &title,
              const std::string  &description)
  {
#ifdef FETICONTACT_WITH_FCLIB
    // libfclib takes non-const pointers but only reads through them when writing.
    auto as_fclib = [](const FclibProblem::CompressedColumns &A) {
      fclib_matrix m{};
      m.nzmax = static_cast<int>(A.value.size());
      m.m     = A.n_rows;
      m.n     = A.n_columns;
      m.p     = const_cast<int *>(A.column_start.data());
      m.i     = const_cast<int *>(A.row.data());
      m.x     = const_cast<double *>(A.value.data());
      m.nz    = -1; // compressed columns
      m.info  = nullptr;
      return m;
    };
    fclib_matrix M = as_fclib(problem.M), H = as_fclib(problem.H);
    const bool   nondimensional = problem.units == Parameters::Output::FclibUnits::nondimensional;
    const FclibScales &scales   = problem.scales;
    std::ostringstream units;
    units << std::setprecision(std::numeric_limits<double>::max_digits10);
    if (nondimensional)
      units << "Units: nondimensional. Length scale L = " << scales.length
            << " m, stress scale S = " << scales.stress
            << " Pa, force scale S L^2 = " << scales.force
            << " N, stiffness scale S L = " << scales.stiffness
            << " N/m = E_max h_c (E_max = " << scales.youngs_modulus
            << " Pa the largest Young's modulus, h_c = " << scales.contact_spacing
            << " m the square root of the contact area per contact node); S L^2 = max(max |f|, "
               "S L max |w|) in SI. SI values: v, u, w times L; r, f times S L^2; M times S L.";
    else
      units << "Units: SI (v, u, w in m; r, f in N; M in N/m).";
    const std::string full_description = description + "\n" + units.str();
    std::string       math_info =
      "M symmetric positive semidefinite (definite when every body is held by prescribed "
      "displacements); quasi-static: v, u are displacements, r forces";
    fclib_info   info{const_cast<char *>(title.c_str()),
                    const_cast<char *>(full_description.c_str()),
                    math_info.data()};
    fclib_global global{};
    global.M        = &M;
    global.H        = &H;
    global.G        = nullptr;
    global.mu       = const_cast<double *>(problem.mu.data());
    global.f        = const_cast<double *>(problem.f.data());
    global.b        = nullptr;
    global.w        = const_cast<double *>(problem.w.data());
    global.spacedim = 3;
    global.info     = &info;

    // libfclib refuses to write into a file that holds a problem already.
    std::filesystem::remove(file);
    if (fclib_write_global(&global, file.c_str()) != 1)
      throw std::runtime_error("FCLIB: writing the problem to " + file + " failed");
    fclib_solution solution{const_cast<double *>(problem.v.data()),
                            const_cast<double *>(problem.u.data()),
                            const_cast<double *>(problem.r.data()),
                            nullptr};
    if (fclib_write_solution(&solution, file.c_str()) != 1)
      throw std::runtime_error("FCLIB: writing the solution to " + file + " failed");

    // The units and scales, as attributes of the root group. These HDF5 calls go to the HDF5
    // that deal.II links (its hdf5.h is first on the include path); libfclib has its own serial
    // HDF5. Each library opens and closes the file on its own.
    const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (h5 < 0)
      throw std::runtime_error("FCLIB: HDF5 cannot open " + file + " to write the scales");
    try
      {
        write_root_attribute(h5, "units", std::string(nondimensional ? "nondimensional" : "SI"));
        write_root_attribute(h5, "length_scale", scales.length);
        write_root_attribute(h5, "stress_scale", scales.stress);
        write_root_attribute(h5, "force_scale", scales.force);
      }
    catch (...)
      {
        H5Fclose(h5);
        throw;
      }
    if (H5Fclose(h5) < 0)
      throw std::runtime_error("FCLIB: HDF5 cannot close " + file);
#else
    (void)problem;
    (void)title;
    (void)description;
    throw std::runtime_error("cannot write " + file +
                             ": this build has no FCLIB (install libfclib-dev, then run cmake "
                             "again)");
#endif
  }
} // namespace FetiContact
