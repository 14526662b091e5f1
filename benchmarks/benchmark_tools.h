#pragma once

// Small helpers shared by the benchmark programs: command-line numbers, medians, and scenes
// given as parameter-file text.

#include <deal.II/base/parameter_handler.h>

#include <feticontact/scene/scene_parameters.h>

#include <algorithm>
#include <iostream>
#include <map>
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

  /**
   * The "--name value" pairs of a benchmark's command line, for the option names @p names.
   * help: "-h" or "--help" was given; ok: false after an unknown option or one without a value
   * (the reason printed on stderr).
   */
  struct CommandLine
  {
    std::map<std::string, std::string> values;
    bool                               help = false;
    bool                               ok   = true;

    /**
     * The positive integer given for @p name, @p fallback if it was not given; 0 (with the
     * reason printed) if its value is not a positive integer.
     */
    unsigned int
    positive(const std::string &name, const unsigned int fallback) const
    {
      const auto it = values.find(name);
      if (it == values.end())
        return fallback;
      const unsigned int number = parse_positive(it->second);
      if (number == 0)
        std::cerr << "Bad value <" << it->second << "> for " << name << ".\n";
      return number;
    }
  };

  /** Reads "--name value" pairs for the option names @p names from the command line. */
  inline CommandLine
  parse_command_line(const int argc, char **argv, const std::vector<std::string> &names)
  {
    CommandLine line;
    for (int a = 1; a < argc; ++a)
      {
        const std::string arg = argv[a];
        if (arg == "--help" || arg == "-h")
          {
            line.help = true;
            return line;
          }
        if (a + 1 >= argc || std::find(names.begin(), names.end(), arg) == names.end())
          {
            std::cerr << "Bad argument <" << arg << ">.\n";
            line.ok = false;
            return line;
          }
        line.values[arg] = argv[++a];
      }
    return line;
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
    scene.parse_parameters(prm);
    return scene;
  }
} // namespace FetiContact::BenchmarkTools
