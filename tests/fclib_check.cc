// Reads an FCLIB file written by feticontact (Output/Write FCLIB problem) back with libfclib
// alone (no deal.II, no feticontact code) and checks that the stored solution solves the stored
// global problem (doc/fclib.md):
//
//   M v = H r + f,   u = Hᵀ v + w,   C*_μ ∋ u + [μ‖u_T‖, 0, 0] ⊥ r ∈ C_μ per contact.
//
// Usage: fclib_check FILE N_DOFS N_CONTACTS TOLERANCE
// N_DOFS and N_CONTACTS are the sizes the scene must have; TOLERANCE bounds the relative
// residuals of equilibrium and of the Coulomb conditions (the natural map, scaled). Exit 0 if
// every check holds, 1 with the failed checks listed otherwise.

// fclib.h declares its C functions without extern "C".
extern "C"
{
#include <fclib.h>
}

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
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
  if (argc != 5)
    {
      std::cerr << "usage: fclib_check FILE N_DOFS N_CONTACTS TOLERANCE\n";
      return 2;
    }
  const std::string file       = argv[1];
  const int         n_dofs     = std::atoi(argv[2]);
  const int         n_contacts = std::atoi(argv[3]);
  const double      tolerance  = std::atof(argv[4]);

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
