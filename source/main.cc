/**
 * feticontact: 3D contact problems of elastic bodies solved by FETI domain decomposition.
 *
 *   feticontact scene.prm                 run the scene
 *   feticontact --validate scene.prm      parse and check the parameter file, then exit
 *   feticontact --set "Body 1/Mesh/Subdivisions=24, 8, 8" scene.prm   override an entry
 *   feticontact --set "Refinement study/Subdivision factors=1, 2" scene.prm   a refinement study
 *   feticontact --print-parameters        every parameter with its default and documentation
 *   feticontact --help
 */

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_start.h>
#include <feticontact/base/output_files.h>
#include <feticontact/base/output_lock.h>
#include <feticontact/base/subdomain_threads.h>
#include <feticontact/core/refinement_study.h>
#include <feticontact/core/simulator.h>
#include <feticontact/scene/parameter_file.h>
#include <feticontact/scene/scene_parameters.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

namespace
{
  void
  print_usage(std::ostream &out)
  {
    out
      << "Usage: feticontact [--validate] [--set PATH=VALUE]... FILE.prm\n"
         "       feticontact --print-parameters\n"
         "       feticontact --help\n\n"
         "Solves the scene described by the deal.II parameter file FILE.prm (linear elastic\n"
         "bodies on P1 tetrahedra, decomposed into FETI subdomains) and writes log.txt,\n"
         "summary.json, the effective parameters and ParaView files into the folder given by\n"
         "'subsection Output / set Directory'. Run under mpirun for several ranks.\n\n"
         "  --validate           parse and check the parameter file and the meshes it names,\n"
         "                       then exit (status 0 if valid)\n"
         "  --set PATH=VALUE     override an entry after reading the file, e.g.\n"
         "                       --set \"Body 1/Mesh/Subdivisions=24, 8, 8\"\n"
         "  --print-parameters   print every parameter with its default and documentation\n"
         "  --help               this text\n\n"
         "Exit status: 0 success, 1 bad input or unwritable output, 2 the solver did not converge\n"
         "or the independent check refutes its answer, 3 internal error, 4 no equilibrium.\n";
  }

  /**
   * Whether a --set entry ends in a backslash, which deal.II would read as a line continuation,
   * joining the next entry to this one.
   */
  bool
  ends_in_backslash(const std::string &entry)
  {
    const std::string value = FetiContact::InputParsing::trim(entry);
    return !value.empty() && value.back() == '\\';
  }

  /** What the command line asks for; `exit_status` set when it is answered already. */
  struct CommandLine
  {
    bool                     validate_only = false;
    std::string              filename;
    std::vector<std::string> overrides;
    std::optional<int>       exit_status;
  };

  /** Reads the options; answers --help and --print-parameters and refuses bad options. */
  CommandLine
  parse_command_line(const std::vector<std::string> &args, const bool root)
  {
    using namespace FetiContact;
    CommandLine command;
    for (unsigned int i = 0; i < args.size() && !command.exit_status; ++i)
      {
        const std::string &a = args[i];
        if (a == "--help" || a == "-h")
          {
            if (root)
              print_usage(std::cout);
            command.exit_status = 0;
          }
        else if (a == "--print-parameters")
          {
            dealii::ParameterHandler prm;
            Parameters::Scene::declare_parameters(prm, 1, 1);
            if (root)
              prm.print_parameters(std::cout, dealii::ParameterHandler::PRM);
            command.exit_status = 0;
          }
        else if (a == "--validate")
          command.validate_only = true;
        else if (a == "--set" && i + 1 < args.size())
          {
            command.overrides.push_back(args[++i]);
            if (ends_in_backslash(command.overrides.back()))
              {
                if (root)
                  std::cerr << "Error: --set <" << command.overrides.back()
                            << ">: a value must not end in a backslash (a parameter file reads "
                               "it as a line continuation).\n";
                command.exit_status = 1;
              }
          }
        else if (!a.empty() && a[0] == '-')
          {
            if (root)
              {
                std::cerr << "Error: unknown option <" << a << ">.\n\n";
                print_usage(std::cerr);
              }
            command.exit_status = 1;
          }
        else if (command.filename.empty())
          command.filename = a;
        else
          {
            if (root)
              std::cerr << "Error: more than one parameter file given.\n";
            command.exit_status = 1;
          }
      }
    if (!command.exit_status && command.filename.empty())
      {
        if (root)
          print_usage(std::cerr);
        command.exit_status = 1;
      }
    return command;
  }

  /**
   * A run claims its output directory (OutputLock: refused if another run holds it) and starts
   * with it free of every file an earlier run wrote there, also when it then stops on bad input.
   * Collective; rank 0 holds @p lock.
   */
  void
  claim_output_directory(const MPI_Comm           comm,
                         const bool               root,
                         const CommandLine       &command,
                         FetiContact::OutputLock &lock)
  {
    using namespace FetiContact;
    std::string error;
    try
      {
        const std::string directory =
          Parameters::Scene::output_directory(command.filename, command.overrides);
        if (root && !directory.empty())
          {
            lock.acquire(directory);
            if (!lock.note().empty())
              std::cerr << "Warning: " << lock.note() << std::endl;
            OutputFiles::clean(directory, command.filename);
          }
      }
    catch (const InputError &e)
      {
        error = e.what();
      }
    OutputFiles::throw_if_any_failed(comm, error);
  }

  /** The message and the exit status of a run that did not converge. */
  int
  report_failure(const FetiContact::Simulator &simulator, const bool root)
  {
    if (root)
      {
        if (simulator.no_equilibrium())
          std::cerr << "Error: " << simulator.solver_message()
                    << ". No displacement or contact files were written (summary.json and "
                       "log.txt say why)."
                    << std::endl;
        else if (!simulator.solver_message().empty() && simulator.solver_message() != "converged")
          std::cerr << "Error: " << simulator.solver_message()
                    << " (see log.txt; summary.json has \"converged\": false)." << std::endl;
        else
          std::cerr << "Error: the FETI solver did not converge (see log.txt; "
                       "summary.json has \"converged\": false)."
                    << std::endl;
      }
    return simulator.no_equilibrium() ? 4 : 2;
  }

  /** The run (or the validation, or the refinement study) of the parameter file. */
  int
  run(const MPI_Comm comm, const bool root, const CommandLine &command)
  {
    using namespace FetiContact;
    // --validate writes nothing and removes nothing.
    OutputLock lock;
    if (!command.validate_only)
      claim_output_directory(comm, root, command, lock);

    dealii::ParameterHandler prm;
    std::vector<std::string> warnings;
    const auto               origins =
      Parameters::Scene::read_parameter_file(prm, command.filename, command.overrides, &warnings);
    if (root)
      for (const auto &w : warnings)
        std::cerr << "Warning: " << w << std::endl;
    Parameters::Scene scene;
    scene.parse_parameters(prm, origins);

    if (command.validate_only)
      {
        // The set-up of a run (the meshes, boundary parts, contact surfaces and the files the
        // scene names) without solving, if they fit into memory, and without writing a file.
        Simulator(comm, scene, "", "").validate();
        if (root)
          std::cout << "The parameter file <" << command.filename << "> is valid." << std::endl;
        return 0;
      }

    const std::string verbatim =
      Parameters::ParameterFileText::bytes_of(command.filename, "parameter file");

    if (!scene.refinement_study.subdivision_factors.empty())
      {
        RefinementStudy study(comm, command.filename, command.overrides, verbatim);
        if (study.run())
          return 0;
        if (root)
          std::cerr << "Error: " << study.message() << "." << std::endl;
        return 2;
      }

    std::ostringstream effective;
    prm.print_parameters(effective, dealii::ParameterHandler::PRM);
    Simulator simulator(comm, scene, effective.str(), verbatim);
    return simulator.run() ? 0 : report_failure(simulator, root);
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace FetiContact;
  MPIStart::prepare_singleton();
  // deal.II's own threads stay off (SubdomainThreads: the subdomains' local work is threaded).
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  SubdomainThreads::initialize(comm);

  const CommandLine command =
    parse_command_line(std::vector<std::string>(argv + 1, argv + argc), root);
  if (command.exit_status)
    return *command.exit_status;
  try
    {
      // A parameter file from a pipe is read once, by rank 0, and kept.
      Parameters::ParameterFileText::share_unrepeatable(comm, command.filename);
      return run(comm, root, command);
    }
  catch (const InputError &e)
    {
      if (root)
        std::cerr << "Error: " << e.what() << std::endl;
      return 1;
    }
  catch (const std::exception &e)
    {
      std::cerr << "Internal error on rank " << dealii::Utilities::MPI::this_mpi_process(comm)
                << ": " << e.what() << std::endl;
      MPI_Abort(comm, 3);
      return 3;
    }
}
