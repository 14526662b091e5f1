// Reads an FCLIB file written by feticontact (Output/Write FCLIB problem) back with libfclib
// alone (no deal.II, no feticontact code) and checks that the stored solution solves the stored
// global problem (doc/fclib.md):
//
//   M v = H r + f,   u = Hᵀ v + w,   C*_μ ∋ u + [μ‖u_T‖, 0, 0] ⊥ r ∈ C_μ per contact.
//
// Usage: fclib_check FILE N_DOFS N_CONTACTS TOLERANCE UNITS [SI_FILE]
// N_DOFS and N_CONTACTS are the sizes the scene must have; TOLERANCE bounds the relative
// residuals of equilibrium and of the Coulomb conditions (the natural map, scaled). UNITS (SI or
// nondimensional) is what the root attribute `units` of FILE must say; the attributes
// length_scale L, stress_scale S and force_scale S L² must be 1 in SI and positive with
// force_scale = S L² otherwise. A nondimensional FILE must be of order one: the largest entries
// of M, f, v, u and r between 1e-2 and 1e2. With SI_FILE, the SI file of the same scene and
// solve, FILE times its scales must be SI_FILE to 1e-12 (relative to the largest entry of each
// array). Exit 0 if every check holds, 1 with the failed checks listed otherwise.

// fclib.h declares its C functions without extern "C".
extern "C"
{
#include <fclib.h>
}

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <iostream>
#include <string>
#include <tuple>
#include <vector>

namespace
{
  int failures = 0;

  void
  check(const bool ok, const std::string &what, const double value, const double bound)
  {
    std::cout << (ok ? "ok     " : "FAILED ") << what << ": " << value << " (bound " << bound
              << ")\n";
    if (!ok)
      ++failures;
  }

  double
  max_abs(const std::vector<double> &x)
  {
    double m = 0;
    for (const double v : x)
      m = std::max(m, std::abs(v));
    return m;
  }

  /** y += A x (transpose: y += Aᵀ x) for a compressed-column fclib_matrix. */
  void
  multiply_add(const fclib_matrix &A, const double *x, double *y, const bool transpose)
  {
    for (int j = 0; j < A.n; ++j)
      for (int p = A.p[j]; p < A.p[j + 1]; ++p)
        {
          if (transpose)
            y[j] += A.x[p] * x[A.i[p]];
          else
            y[A.i[p]] += A.x[p] * x[j];
        }
  }

  /** The units and scales a file stores as attributes of its root group. */
  struct Units
  {
    std::string name;
    double      length = 0, stress = 0, force = 0;
  };

  /** Reads the attributes units, length_scale, stress_scale, force_scale of @p file. */
  bool
  read_units(const std::string &file, Units &units)
  {
    const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (h5 < 0)
      return false;
    bool        ok = true;
    hsize_t     dims[1]{0};
    H5T_class_t type_class;
    size_t      size = 0;
    if (H5LTget_attribute_info(h5, "/", "units", dims, &type_class, &size) < 0 ||
        type_class != H5T_STRING)
      ok = false;
    else
      {
        std::vector<char> text(size + 1, '\0');
        ok         = H5LTget_attribute_string(h5, "/", "units", text.data()) >= 0;
        units.name = text.data();
      }
    ok = ok && H5LTget_attribute_double(h5, "/", "length_scale", &units.length) >= 0 &&
         H5LTget_attribute_double(h5, "/", "stress_scale", &units.stress) >= 0 &&
         H5LTget_attribute_double(h5, "/", "force_scale", &units.force) >= 0;
    H5Fclose(h5);
    return ok;
  }

  /**
   * The largest difference of @p x times @p scale from @p reference (both of size @p n),
   * relative to max |reference|.
   */
  double
  scaled_difference(const double *x, const double *reference, const int n, const double scale)
  {
    double d = 0, largest = 0;
    for (int i = 0; i < n; ++i)
      {
        d       = std::max(d, std::abs(x[i] * scale - reference[i]));
        largest = std::max(largest, std::abs(reference[i]));
      }
    return largest > 0 ? d / largest : d;
  }

  /** Projection of (r_N, r_T1, r_T2) on the cone ‖r_T‖ ≤ μ r_N. */
  void
  project_on_cone(double r[3], const double mu)
  {
    const double t = std::hypot(r[1], r[2]);
    if (t <= mu * r[0])
      return;
    if (mu * t <= -r[0])
      {
        r[0] = r[1] = r[2] = 0;
        return;
      }
    const double n = (mu * t + r[0]) / (mu * mu + 1);
    r[1] *= mu * n / t;
    r[2] *= mu * n / t;
    r[0] = n;
  }
} // namespace

int
main(int argc, char **argv)
{
  if (argc != 6 && argc != 7)
    {
      std::cerr << "usage: fclib_check FILE N_DOFS N_CONTACTS TOLERANCE UNITS [SI_FILE]\n";
      return 2;
    }
  const std::string file       = argv[1];
  const int         n_dofs     = std::atoi(argv[2]);
  const int         n_contacts = std::atoi(argv[3]);
  const double      tolerance  = std::atof(argv[4]);
  const std::string units_name = argv[5];
  const std::string si_file    = argc == 7 ? argv[6] : "";
  if (units_name != "SI" && units_name != "nondimensional")
    {
      std::cerr << "fclib_check: UNITS must be SI or nondimensional\n";
      return 2;
    }

  fclib_global   *problem  = fclib_read_global(file.c_str());
  fclib_solution *solution = problem ? fclib_read_solution(file.c_str()) : nullptr;
  if (!problem || !solution)
    {
      std::cerr << "fclib_check: libfclib cannot read the problem and solution of " << file << '\n';
      return 1;
    }
  const fclib_matrix &M = *problem->M, &H = *problem->H;

  // Sizes and storage.
  check(problem->spacedim == 3, "spacedim = 3", problem->spacedim, 3);
  check(M.m == n_dofs && M.n == n_dofs, "M is N_DOFS × N_DOFS", M.m, n_dofs);
  check(H.m == n_dofs && H.n == 3 * n_contacts, "H is N_DOFS × 3 N_CONTACTS", H.n, 3 * n_contacts);
  check(M.nz == -1 && H.nz == -1, "M, H in compressed columns", M.nz, -1);
  check(problem->G == nullptr, "no equality block G", 0, 0);
  if (failures > 0)
    return 1;
  const int n = M.n, m = H.n, nc = m / 3;

  // M symmetric: Σ over entries of M − Mᵀ, by comparing column j with row j.
  {
    double              asymmetry = 0, largest = 0;
    std::vector<double> row(n, 0.0);
    for (int j = 0; j < n; ++j)
      for (int p = M.p[j]; p < M.p[j + 1]; ++p)
        largest = std::max(largest, std::abs(M.x[p]));
    for (int j = 0; j < n; ++j)
      for (int p = M.p[j]; p < M.p[j + 1]; ++p)
        {
          const int i   = M.i[p];
          double    mji = 0; // M(j, i): column i, row j
          for (int q = M.p[i]; q < M.p[i + 1]; ++q)
            if (M.i[q] == j)
              mji = M.x[q];
          asymmetry = std::max(asymmetry, std::abs(M.x[p] - mji));
        }
    check(asymmetry <= 1e-12 * largest,
          "M symmetric (max |M − Mᵀ| / max |M|)",
          asymmetry / largest,
          1e-12);
  }

  const std::vector<double> v(solution->v, solution->v + n), u(solution->u, solution->u + m),
    r(solution->r, solution->r + m), f(problem->f, problem->f + n), w(problem->w, problem->w + m);
  const double M_max = max_abs(std::vector<double>(M.x, M.x + M.p[n]));
  std::cout << "       max |M| = " << M_max << ", max |f| = " << max_abs(f)
            << ", max |w| = " << max_abs(w) << ", max |v| = " << max_abs(v)
            << ", max |u| = " << max_abs(u) << ", max |r| = " << max_abs(r) << '\n';

  // The units and scales stored in the file.
  Units units;
  if (!read_units(file, units))
    {
      check(false, "root attributes units, length_scale, stress_scale, force_scale", 0, 0);
      return 1;
    }
  std::cout << "       units = " << units.name << ", length_scale = " << units.length
            << ", stress_scale = " << units.stress << ", force_scale = " << units.force << '\n';
  check(units.name == units_name, "units = " + units_name, units.name == units_name, 1);
  if (units_name == "SI")
    check(units.length == 1 && units.stress == 1 && units.force == 1,
          "SI: the scales are 1",
          std::max(
            {std::abs(units.length - 1), std::abs(units.stress - 1), std::abs(units.force - 1)}),
          0);
  else
    {
      check(units.length > 0 && units.stress > 0 && std::isfinite(units.length) &&
              std::isfinite(units.stress),
            "length and stress scales positive",
            std::min(units.length, units.stress),
            0);
      const double force = units.stress * units.length * units.length;
      check(std::abs(units.force - force) <= 1e-15 * force,
            "force_scale = stress_scale length_scale² (relative)",
            std::abs(units.force - force) / force,
            1e-15);
      // Of order one (in SI, M, f and r are 1e5 to 1e11, v and u below 1e-3).
      for (const auto &[name, value] :
           std::vector<std::pair<std::string, double>>{{"M", M_max},
                                                       {"f", max_abs(f)},
                                                       {"v", max_abs(v)},
                                                       {"u", max_abs(u)},
                                                       {"r", max_abs(r)}})
        check(value >= 1e-2 && value <= 1e2, "max |" + name + "| in [1e-2, 1e2]", value, 1e2);
    }

  // FILE times its scales is the SI file: the same problem and solution in other units.
  if (!si_file.empty())
    {
      fclib_global   *si          = fclib_read_global(si_file.c_str());
      fclib_solution *si_solution = si ? fclib_read_solution(si_file.c_str()) : nullptr;
      if (!si || !si_solution)
        {
          std::cerr << "fclib_check: libfclib cannot read the problem and solution of " << si_file
                    << '\n';
          return 1;
        }
      const fclib_matrix &M_si = *si->M, &H_si = *si->H;
      const bool          same_pattern =
        M_si.m == M.m && M_si.n == M.n && H_si.m == H.m && H_si.n == H.n && M_si.nz == -1 &&
        H_si.nz == -1 && std::equal(M.p, M.p + n + 1, M_si.p) &&
        std::equal(H.p, H.p + m + 1, H_si.p) && std::equal(M.i, M.i + M.p[n], M_si.i) &&
        std::equal(H.i, H.i + H.p[m], H_si.i);
      check(same_pattern, "the SI file has the same sizes and sparsity", same_pattern, 1);
      if (same_pattern)
        {
          const double L = units.length, S = units.stress, F = units.force;
          const std::vector<std::tuple<std::string, const double *, const double *, int, double>>
            arrays{{"M", M.x, M_si.x, M.p[n], S * L},
                   {"H", H.x, H_si.x, H.p[m], 1},
                   {"f", problem->f, si->f, n, F},
                   {"w", problem->w, si->w, m, L},
                   {"mu", problem->mu, si->mu, nc, 1},
                   {"v", solution->v, si_solution->v, n, L},
                   {"u", solution->u, si_solution->u, m, L},
                   {"r", solution->r, si_solution->r, m, F}};
          for (const auto &[name, x, reference, size, scale] : arrays)
            {
              const double d = scaled_difference(x, reference, size, scale);
              check(d <= 1e-12,
                    name + " × scale = " + name + " of the SI file (relative)",
                    d,
                    1e-12);
            }
        }
      fclib_delete_global(si);
      free(si);
      fclib_delete_solutions(si_solution, 1);
    }

  // u = Hᵀ v + w.
  {
    std::vector<double> Hv = w;
    multiply_add(H, v.data(), Hv.data(), true);
    double d = 0;
    for (int j = 0; j < m; ++j)
      d = std::max(d, std::abs(Hv[j] - u[j]));
    check(d <= 1e-12 * max_abs(u), "u = Hᵀ v + w (relative to max |u|)", d / max_abs(u), 1e-12);
  }

  // Equilibrium M v = H r + f, relative to the largest of the three terms.
  {
    std::vector<double> Mv(n, 0.0), Hr(n, 0.0), residual(n);
    multiply_add(M, v.data(), Mv.data(), false);
    multiply_add(H, r.data(), Hr.data(), false);
    for (int i = 0; i < n; ++i)
      residual[i] = Mv[i] - Hr[i] - f[i];
    const double scale = std::max({max_abs(Mv), max_abs(Hr), max_abs(f)});
    check(max_abs(residual) <= tolerance * scale,
          "M v − H r − f (relative)",
          max_abs(residual) / scale,
          tolerance);
  }

  // The Coulomb conditions of every contact. Natural map: r − P_C(r − ρ û), û = u + μ‖u_T‖ e_N,
  // with ρ = max |r| / max |u| so that forces and displacements weigh alike; relative to max |r|.
  {
    const double r_max = max_abs(r), u_max = max_abs(u), rho = r_max / u_max;
    double       natural = 0, negative_force = 0, penetration = 0, cone = 0;
    int          pressed = 0;
    for (int k = 0; k < nc; ++k)
      {
        const double *rk = &r[3 * k], *uk = &u[3 * k], mu = problem->mu[k];
        negative_force = std::max(negative_force, -rk[0]);
        penetration    = std::max(penetration, -uk[0]);
        cone           = std::max(cone, std::hypot(rk[1], rk[2]) - mu * rk[0]);
        pressed += rk[0] > 0 ? 1 : 0;
        const double ut = std::hypot(uk[1], uk[2]);
        double z[3]{rk[0] - rho * (uk[0] + mu * ut), rk[1] - rho * uk[1], rk[2] - rho * uk[2]};
        project_on_cone(z, mu);
        natural =
          std::max(natural, std::hypot(rk[0] - z[0], std::hypot(rk[1] - z[1], rk[2] - z[2])));
      }
    check(pressed > 0, "some contact pressed", pressed, 1);
    check(negative_force <= tolerance * r_max,
          "r_N ≥ 0 (relative)",
          negative_force / r_max,
          tolerance);
    check(penetration <= tolerance * u_max, "u_N ≥ 0 (relative)", penetration / u_max, tolerance);
    check(cone <= tolerance * r_max, "‖r_T‖ ≤ μ r_N (relative)", cone / r_max, tolerance);
    check(natural <= tolerance * r_max,
          "natural map r − P_C(r − ρ û) (relative)",
          natural / r_max,
          tolerance);
  }

  fclib_delete_global(problem);
  free(problem);
  fclib_delete_solutions(solution, 1);
  return failures == 0 ? 0 : 1;
}
