#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/json_writer.h>
#include <feticontact/base/output_files.h>
#include <feticontact/core/memory_estimate.h>
#include <feticontact/core/refinement_study.h>
#include <feticontact/core/simulator.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  RefinementStudy::RefinementStudy(const MPI_Comm                  comm,
                                   const std::string              &filename,
                                   const std::vector<std::string> &overrides,
                                   const std::string              &input)
    : comm(comm)
    , filename(filename)
    , overrides(overrides)
    , input(input)
  {}

  bool
  RefinementStudy::run()
  {
    const bool       root = Utilities::MPI::this_mpi_process(comm) == 0;
    ParameterHandler base_prm;
    const auto origins = Parameters::Scene::read_parameter_file(base_prm, filename, overrides);
    Parameters::Scene base;
    base.parse_parameters(base_prm, origins);
    const std::string directory = base.output.directory;
    // (main() has removed every file of an earlier run from the directory.)

    ConvergenceTable                           table;
    std::map<std::string, std::vector<double>> columns;
    const auto                                 add = [&](const std::string &key, const auto value) {
      table.add_value(key, value);
      columns[key].push_back(double(value));
    };
    const auto &factors = base.refinement_study.subdivision_factors;
    // Every cycle's scene first, so that a study whose finest cycle does not fit into memory
    // stops before its first solve.
    std::vector<Cycle> cycles;
    for (unsigned int cycle = 0; cycle < factors.size(); ++cycle)
      {
        cycles.push_back(make_cycle(base, cycle));
        MemoryEstimate::of(cycles.back().scene, comm).check(cycles.back().scene);
      }
    for (unsigned int cycle = 0; cycle < factors.size(); ++cycle)
      {
        const Cycle &c = cycles[cycle];
        if (root)
          std::cout << "\nRefinement study: cycle " << cycle + 1 << " of " << factors.size()
                    << ", factor " << factors[cycle] << ", subdivisions " << c.subdivisions
                    << ", output in " << c.directory << std::endl;

        Simulator simulator(comm, c.scene, c.effective_parameters, input);
        if (!simulator.run())
          {
            failure = "refinement study: cycle " + std::to_string(cycle + 1) + " (factor " +
                      InputParsing::number_text(factors[cycle]) +
                      "): " + simulator.solver_message() + " (see " + c.directory + "/log.txt)";
            break;
          }
        const auto &s = simulator.statistics();
        table.add_value("cycle", cycle + 1);
        columns["cycle"].push_back(cycle + 1);
        add("factor", factors[cycle]);
        add("unknowns", s.n_primal);
        add("contact nodes", s.n_contact_nodes);
        add("h_min", s.h_min);
        add("Iter", s.outer_iterations);
        add("n_A", s.hessian_multiplications);
        add("solve [s]", s.solve_time);
        if (s.hertz)
          {
            add("a", s.hertz->a);
            add("a error", s.hertz->a_error());
            add("p0", s.hertz->p0);
            add("p0 error", s.hertz->p0_error());
          }
      }

    if (!columns.empty())
      {
        for (const std::string key : {"h_min", "a", "a error", "p0", "p0 error"})
          if (columns.count(key))
            {
              table.set_scientific(key, true);
              table.set_precision(key, 3);
            }
        table.set_precision("solve [s]", 2);
        for (const std::string key : {"a error", "p0 error"})
          if (columns.count(key))
            // Every cell's size is h/factor: the grading and the spherical bottom are fixed
            // maps of the box, refined uniformly by the factor.
            table.evaluate_convergence_rates(key,
                                             "factor",
                                             ConvergenceTable::reduction_rate_log2,
                                             1);
        std::string error;
        if (root)
          try
            {
              std::cout << "\nRefinement study (" << directory << "/convergence_table.txt):\n";
              table.write_text(std::cout, TableHandler::table_with_headers);
              ResultFiles files;
              write_table(table, files, directory);
              JsonObject json;
              for (const auto &[key, values] : columns)
                json.set(key, values);
              files.open(directory + "/refinement_study.json") << json.str() << '\n';
              files.commit();
            }
          catch (const OutputError &e)
            {
              error = e.what();
            }
        OutputFiles::throw_if_any_failed(comm, error);
      }
    return failure.empty();
  }

  RefinementStudy::Cycle
  RefinementStudy::make_cycle(const Parameters::Scene &base, const unsigned int cycle) const
  {
    const double             factor          = base.refinement_study.subdivision_factors[cycle];
    std::vector<std::string> cycle_overrides = overrides;
    std::ostringstream       subdivisions;
    for (unsigned int b = 0; b < base.bodies.size(); ++b)
      {
        std::ostringstream entry;
        entry << "Body " << b + 1 << "/Mesh/Subdivisions=";
        for (unsigned int d = 0; d < 3; ++d)
          {
            const long n = std::max(1L, std::lround(base.bodies[b].mesh.subdivisions[d] * factor));
            entry << (d > 0 ? ", " : "") << n;
            subdivisions << (d > 0 ? "×" : (b > 0 ? "; " : "")) << n;
          }
        cycle_overrides.push_back(entry.str());
      }
    Cycle c;
    c.subdivisions = subdivisions.str();
    c.directory    = base.output.directory + "/cycle-" + std::to_string(cycle + 1);
    cycle_overrides.push_back("Output/Directory=" + c.directory);

    ParameterHandler prm;
    const auto origins = Parameters::Scene::read_parameter_file(prm, filename, cycle_overrides);
    c.scene.parse_parameters(prm, origins);
    std::ostringstream effective;
    prm.print_parameters(effective, ParameterHandler::PRM);
    c.effective_parameters = effective.str();
    return c;
  }

  void
  RefinementStudy::write_table(ConvergenceTable  &table,
                               ResultFiles       &files,
                               const std::string &directory) const
  {
    files.write(directory + "/convergence_table.txt", [&](std::ostream &out) {
      table.write_text(out, TableHandler::table_with_headers);
    });
    files.write(directory + "/convergence_table.org",
                [&](std::ostream &out) { table.write_text(out, TableHandler::org_mode_table); });
  }
} // namespace FetiContact
