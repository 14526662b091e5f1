#pragma once

// Small helpers shared by the benchmark programs: command-line numbers, medians, and scenes
// given as parameter-file text.

#include <deal.II/base/parameter_handler.h>

#include <feticontact/scene/scene_parameters.h>

#include <algorithm>
#include <string>
#include <vector>

namespace FetiContact::BenchmarkTools
{
  /** A positive integer, or 0 if @p text is not one. */
  inline unsigned int
  parse_positive(const std::string &text)
  {
    if (text.empty() || text.size() > 9 ||
        !std::all_of(text.begin(), text.end(), [](const char c) { return c >= '0' && c <= '9'; }))
      return 0;
    return std::stoul(text);
  }

  /** The median of @p v (the mean of the two middle values for an even count). */
  inline double
  median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }

  /** The scene of a parameter file given as @p text, defaults for everything not set. */
  inline Parameters::Scene
  scene_from_text(const std::string &text)
  {
    dealii::ParameterHandler prm;
    Parameters::Scene::declare_parameters(prm, 1);
    prm.parse_input_from_string(text);
    Parameters::Scene scene;
    scene.parse_parameters(prm, "");
    return scene;
  }
} // namespace FetiContact::BenchmarkTools
