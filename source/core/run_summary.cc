#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/subdomain_threads.h>
#include <feticontact/core/run_summary.h>

#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  void
  SolveWork::record_applications(const DualProblem &dual)
  {
    F_time                      = dual.F_time;
    F_local_time                = dual.F_local_time;
    F_applications              = dual.n_F_applications;
    preconditioner_time         = dual.lumped_time;
    preconditioner_applications = dual.n_lumped_applications;
  }

  namespace RunSummary
  {
    namespace
    {
      /**
       * n_A, the Hessian multiplications of the solve: the applications of F without contact,
       * those of the bound and the disc QPs with it.
       */
      unsigned int
      hessian_multiplications(const Run &run)
      {
        return run.contact.n_nodes() == 0 ? run.dual.n_F_applications :
                                            run.work.n_bound + run.work.n_disc;
      }

      /** The wall time of the phase @p name of @p timer (0 if it did not run). */
      double
      phase_time(const TimerOutput &timer, const std::string &name)
      {
        const auto times = timer.get_summary_data(TimerOutput::total_wall_time);
        const auto it    = times.find(name);
        return it == times.end() ? 0.0 : it->second;
      }

      /**
       * The times of the phases and of the parts of the solve (summary.json: times), and the
       * log line of the solve's parts; @p total: the sum of the phases.
       */
      JsonObject
      summarize_times(const Run &run, ConditionalOStream &pcout, double &total)
      {
        const MPI_Comm comm  = run.comm;
        const auto     times = run.timer.get_summary_data(TimerOutput::total_wall_time);
        const auto     time  = [&](const std::string &name) { return phase_time(run.timer, name); };
        JsonObject     t;
        t.set("setup", time("setup"))
          .set("assembly", time("assembly"))
          .set("factorization", time("factorization"))
          .set("coarse_problem", time("coarse problem"))
          .set("solve", time("solve"))
          .set("primal_recovery", time("primal recovery"))
          .set("output", time("output"))
          .set("contact_rows", Utilities::MPI::max(run.work.contact_rows_time, comm));
        total = 0;
        for (const auto &[name, value] : times)
          total += value;
        t.set("total", total);
        // Inside the solve: the applications of F (local solves with the factors, B, Bᵀ, the sum
        // over ranks; the slowest rank) and the rest, the QP's own work (vector operations,
        // projections, the coarse problem's applications of G). The cost floor of the method is
        // the factorization and n_A applications of F; total_over_floor compares the run without
        // output with it.
        const SolveWork &work         = run.work;
        const double     hessian_time = Utilities::MPI::max(work.F_time, comm);
        const double     mean_F  = work.F_applications > 0 ? hessian_time / work.F_applications : 0;
        const unsigned int n_A   = hessian_multiplications(run);
        const double       floor = time("factorization") + n_A * mean_F;
        // Of the applications of F, the work in the subdomains of the slowest and of the fastest
        // rank; the rest of hessian_applications is the exchange of B u among the ranks and
        // waiting.
        const double local_slowest = Utilities::MPI::max(work.F_local_time, comm);
        const double local_fastest = Utilities::MPI::min(work.F_local_time, comm);
        // The lumped preconditioner (zero when off), the slowest rank.
        const double preconditioner_time = Utilities::MPI::max(work.preconditioner_time, comm);
        const double bookkeeping         = time("solve") - hessian_time - preconditioner_time;
        const double over_floor          = floor > 0 ? (total - time("output")) / floor : 0.0;
        t.set("hessian_applications", hessian_time)
          .set("hessian_local_slowest_rank", local_slowest)
          .set("hessian_local_fastest_rank", local_fastest)
          .set("preconditioner", preconditioner_time)
          .set("preconditioner_applications", work.preconditioner_applications)
          .set("qp_bookkeeping", bookkeeping)
          .set("one_hessian_application", mean_F)
          .set("cost_floor", floor)
          .set("total_over_floor", over_floor);
        // (A stream of its own: the precision of the solver's lines must not carry over.)
        std::ostringstream line;
        line << std::setprecision(4) << "Time: solve " << time("solve") << " s = applications of F "
             << hessian_time << " s (" << work.F_applications << ", " << mean_F
             << " s each; local work " << local_slowest << " s on the slowest rank, "
             << local_fastest << " s on the fastest)";
        if (work.preconditioner_applications > 0)
          line << " + preconditioner " << preconditioner_time << " s ("
               << work.preconditioner_applications << ")";
        line << " + QP bookkeeping " << bookkeeping
             << " s; cost floor (factorization + n_A × one application of F) " << floor
             << " s, run without output / floor " << over_floor;
        pcout << line.str() << std::endl;
        return t;
      }

      /**
       * The memory of the meshes that this rank holds (Triangulation::memory_consumption()):
       * every body's whole mesh, or with distributed cells the rank's own, in MiB.
       */
      double
      meshes_mib(const std::vector<std::unique_ptr<Body>> &bodies)
      {
        std::size_t bytes = 0;
        for (const auto &body : bodies)
          bytes += body->mesh.memory_consumption();
        return static_cast<double>(bytes) / (1024.0 * 1024.0);
      }

      /** The peak memory of every rank and the estimate (summary.json: memory), and its line. */
      JsonObject
      summarize_memory(const Run &run, ConditionalOStream &pcout)
      {
        // Peak resident memory of every rank (the process's high-water mark: meshes, subdomain
        // matrices and factors, dual vectors, the coarse factor, the MPI library; the
        // pages of the coarse factor shared by a node's ranks count on every rank that reads
        // them).
        Utilities::System::MemoryStats stats;
        Utilities::System::get_memory_stats(stats);
        const std::vector<double> peak_mib =
          Utilities::MPI::all_gather(run.comm, static_cast<double>(stats.VmHWM) / 1024.0);
        JsonObject memory;
        memory.set("peak_rss_mib_max", *std::max_element(peak_mib.begin(), peak_mib.end()))
          .set("peak_rss_mib_per_rank", peak_mib)
          .set("estimated_peak_mib", run.memory_estimate.peak_mib)
          .set("model_cells", run.memory_estimate.cells)
          .set("model_factor_units", run.memory_estimate.factor_units)
          .set("meshes_mib", meshes_mib(run.bodies))
          .set("contact_mib",
               static_cast<double>(run.contact.memory_consumption()) / (1024.0 * 1024.0))
          .set("coarse_shared_mib_per_rank",
               Utilities::MPI::all_gather(
                 run.comm,
                 static_cast<double>(run.dual.coarse.shared_factor_bytes()) / (1024.0 * 1024.0)));
        pcout << "Peak resident memory per rank: ";
        for (const double p : peak_mib)
          pcout << std::fixed << std::setprecision(0) << p << " MiB " << std::defaultfloat;
        pcout << std::endl;
        return memory;
      }

      /** The exchanges of one application of F, per rank (DualProblem::communication_volume). */
      JsonObject
      summarize_communication(const Run &run)
      {
        const DualProblem::CommunicationVolume v        = run.dual.communication_volume();
        const auto                             per_rank = [&run](const std::size_t x) {
          return Utilities::MPI::all_gather(run.comm, static_cast<double>(x));
        };
        return JsonObject()
          .set("slot_neighbours_per_rank", per_rank(v.slot_neighbours))
          .set("slots_sent_per_rank", per_rank(v.slots_sent))
          .set("slots_received_per_rank", per_rank(v.slots_received))
          .set("ghost_neighbours_per_rank", per_rank(v.ghost_neighbours))
          .set("ghosts_received_per_rank", per_rank(v.ghosts_received));
      }

      /** How the subdomain solves were shared among the ranks (summary.json: local_work). */
      JsonObject
      summarize_local_work(const Run &run)
      {
        // The subdomain solves each rank made in the multiplications by F.
        return JsonObject().set(
          "subdomain_solves_per_rank",
          Utilities::MPI::all_gather(run.comm, static_cast<double>(run.dual.n_subdomain_solves)));
      }

      /** The smallest cell diameter of all bodies, over all ranks. */
      double
      smallest_cell(const Run &run)
      {
        double h_min = std::numeric_limits<double>::max();
        for (const auto &body : run.bodies)
          if (body->mesh.n_active_cells() > 0)
            h_min = std::min(h_min, GridTools::minimal_cell_diameter(body->mesh));
        return Utilities::MPI::min(h_min, run.comm);
      }
    } // namespace

    void
    set_leading_members(Summary            &summary,
                        const Run          &run,
                        ConditionalOStream &pcout,
                        RunStatistics      &statistics)
    {
      unsigned int n_primal = 0, n_primal_feti = 0;
      for (const auto &body : run.bodies)
        n_primal += body->n_free_dofs();
      for (auto *s : run.owned)
        n_primal_feti += s->n_unknowns();
      n_primal_feti            = Utilities::MPI::sum(n_primal_feti, run.comm);
      const double       h_min = smallest_cell(run);
      const unsigned int n_bound_total =
        run.contact.n_nodes() == 0 ? run.dual.n_F_applications : run.work.n_bound;
      const unsigned int n_A = hessian_multiplications(run);

      double           total_time    = 0;
      const JsonObject times         = summarize_times(run, pcout, total_time);
      const JsonObject memory        = summarize_memory(run, pcout);
      const JsonObject communication = summarize_communication(run);
      const JsonObject local_work    = summarize_local_work(run);
      const auto      &feti          = run.parameters.feti;
      summary.set_leading("converged", run.converged)
        .set_leading("n_primal", n_primal)
        .set_leading("n_primal_feti", n_primal_feti)
        .set_leading("n_subdomains", run.first_subdomain.back())
        .set_leading("n_rigid_modes", run.mode_offset.back())
        .set_leading("h_min", h_min)
        .set_leading("m_total", run.dual.size())
        .set_leading("m_equality", run.layout.n_equality)
        .set_leading("m_contact", run.layout.n_normal + run.layout.n_tangential)
        .set_leading("iterations", run.work.iterations)
        .set_leading("outer_iterations", run.work.iterations)
        .set_leading("hessian_multiplications",
                     JsonObject()
                       .set("bound", n_bound_total)
                       .set("disc", run.work.n_disc)
                       .set("total", n_A)
                       .set("F_applications", run.dual.n_F_applications))
        .set_leading("n_mpi_ranks", Utilities::MPI::n_mpi_processes(run.comm))
        .set_leading("threads_per_rank", SubdomainThreads::n_threads())
        .set_leading("dirichlet_treatment",
                     feti.dirichlet_treatment == Parameters::Feti::DirichletTreatment::primal ?
                       "primal" :
                       "total")
        .set_leading("local_solver", feti.local_solver)
        .set_leading("local_work", local_work)
        .set_leading("times", times)
        .set_leading("memory", memory)
        .set_leading("communication", communication);

      statistics.n_primal                = n_primal;
      statistics.n_contact_nodes         = run.contact.n_nodes();
      statistics.outer_iterations        = run.work.iterations;
      statistics.hessian_multiplications = n_A;
      statistics.h_min                   = h_min;
      statistics.solve_time              = phase_time(run.timer, "solve");
      statistics.time_without_output     = total_time - phase_time(run.timer, "output");
    }

    void
    set_stopped_members(Summary           &summary,
                        const unsigned int n_subdomains,
                        const unsigned int n_contact_nodes,
                        const unsigned int n_ranks)
    {
      summary.set_leading("converged", false)
        .set_leading("n_subdomains", n_subdomains)
        .set_leading("n_contact_nodes", n_contact_nodes)
        .set_leading("n_mpi_ranks", n_ranks);
    }

    void
    set_load_balance(Summary &summary, const LoadBalance &balance)
    {
      const char *outcome[] = {"balanced", "impossible", "undecided"};
      summary.set("load_balance",
                  JsonObject()
                    .set("outcome", outcome[static_cast<int>(balance.outcome)])
                    .set("relative_residual", balance.relative_residual)
                    .set("iterations", balance.iterations));
    }

    void
    set_contact_solver(Summary &summary, const ContactSolver::Result &result)
    {
      summary.set("solver_message", result.message);
      summary.set("no_equilibrium", result.no_equilibrium);
      summary.set("smalbe_iterations", result.smalbe_iterations);
      summary.set("mpgp_steps",
                  JsonObject()
                    .set("cg", result.cg_steps)
                    .set("expansion", result.expansion_steps)
                    .set("proportioning", result.proportioning_steps)
                    .set("expansion_fallbacks", result.expansion_fallbacks)
                    .set("recursive_gradient_updates", result.recursive_gradient_updates));
    }
  } // namespace RunSummary
} // namespace FetiContact
