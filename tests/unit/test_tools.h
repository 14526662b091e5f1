#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/feti/equality_constraints.h>
#include <feticontact/scene/scene_parameters.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

/** Counts failed checks; a test program returns the count (0: passed). */
inline int n_failures = 0;

/** Prints the check with its numbers and counts it if it fails. */
inline void
check(const bool ok, const std::string &what)
{
  std::cout << (ok ? "  ok      " : "  FAILED  ") << what << std::endl;
  if (!ok)
    ++n_failures;
}

/** A number in scientific notation for messages. */
inline std::string
sci(const double v)
{
  std::ostringstream s;
  s.precision(3);
  s << std::scientific << v;
  return s.str();
}

/** The scene of a parameter file given as text (defaults for everything not set). */
inline FetiContact::Parameters::Scene
scene_from_text(const std::string &text)
{
  dealii::ParameterHandler prm;
  FetiContact::Parameters::Scene::declare_parameters(prm, 1);
  prm.parse_input_from_string(text);
  FetiContact::Parameters::Scene scene;
  scene.parse_parameters(prm);
  return scene;
}

/** The brick benchmark of doc/formulation.md (k = 4) with the given decomposition subsection lines.
 */
inline std::string
brick_text(const std::string &decomposition, const unsigned int k = 4)
{
  return "subsection Body 1\n"
         " set Name = brick\n"
         " subsection Mesh\n"
         "  set Lower corner = 0, 0, 0\n"
         "  set Upper corner = 3, 1, 1\n"
         "  set Subdivisions = " +
         std::to_string(3 * k) + ", " + std::to_string(k) + ", " + std::to_string(k) +
         "\n"
         " end\n"
         " subsection Boundary conditions\n"
         "  set Clamped boundaries = x = xmin\n"
         "  set Tractions = z = zmax: 2e7, 0, -1e8; x = xmax: 0, 3e7, 0\n"
         " end\n"
         " subsection Decomposition\n" +
         decomposition +
         "\n end\n"
         "end\n";
}

/** The largest entry of |B Bᵀ − I| over all rows of @p rows. */
inline double
deviation_from_orthonormal(const FetiContact::DualRows &rows)
{
  std::map<std::tuple<unsigned, unsigned, unsigned>, std::vector<std::pair<unsigned, double>>>
    by_dof;
  for (unsigned int r = 0; r < rows.n_rows(); ++r)
    for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
      {
        const auto &e = rows.entries[k];
        by_dof[{e.subdomain, e.body_vertex, e.component}].emplace_back(r, e.value);
      }
  std::map<std::pair<unsigned, unsigned>, double> BBt;
  for (const auto &[dof, list] : by_dof)
    for (const auto &[r, a] : list)
      for (const auto &[s, b] : list)
        BBt[{r, s}] += a * b;
  double deviation = 0;
  for (unsigned int r = 0; r < rows.n_rows(); ++r)
    deviation = std::max(deviation, std::abs(BBt[{r, r}] - 1));
  for (const auto &[rs, value] : BBt)
    if (rs.first != rs.second)
      deviation = std::max(deviation, std::abs(value));
  return deviation;
}
