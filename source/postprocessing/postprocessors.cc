#include <deal.II/base/mpi.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/contact/contact_nodes.h>
#include <feticontact/contact/rigid_obstacle.h>
#include <feticontact/postprocessing/contact_output.h>
#include <feticontact/postprocessing/fclib_export.h>
#include <feticontact/postprocessing/postprocessors.h>
#include <feticontact/postprocessing/solution_output.h>
#include <feticontact/postprocessing/stresses.h>
#include <feticontact/postprocessing/verification.h>
#include <feticontact/scene/decomposition.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace FetiContact::Postprocessing
{
  using namespace dealii;

  bool
  Input::root() const
  {
    return Utilities::MPI::this_mpi_process(comm) == 0;
  }

  void
  Input::on_all_ranks(const std::function<void()> &write) const
  {
    MPITools::collectively<OutputError>(comm, write);
  }

  void
  Input::check(const std::string &key,
               const std::string &description,
               const double       value,
               const double       limit) const
  {
    if (summary.check(key, description, value, limit))
      pcout << "Check failed: " << summary.check_failure() << std::endl;
  }

  std::vector<std::unique_ptr<Interface>>
  create(const Parameters::Scene &parameters, const bool has_contact)
  {
    std::vector<std::unique_ptr<Interface>> list;
    list.push_back(std::make_unique<ConstraintCheck>());
    if (has_contact)
      list.push_back(std::make_unique<ContactConditions>());
    list.push_back(std::make_unique<SmallStrainCheck>());
    if (parameters.verification.hertz.enabled)
      list.push_back(std::make_unique<HertzComparison>());
    list.push_back(std::make_unique<EquilibriumCheck>());
    if (parameters.verification.compare_with_monolithic)
      list.push_back(std::make_unique<MonolithicComparison>());
    if (!parameters.verification.reference_displacements.empty())
      list.push_back(std::make_unique<ReferenceComparison>());
    if (has_contact)
      list.push_back(std::make_unique<ContactOutput>());
    if (parameters.output.write_fclib)
      list.push_back(std::make_unique<FclibExport>());
    if (parameters.output.write_vtu)
      list.push_back(std::make_unique<SolutionOutput>());
    if (parameters.output.write_displacement_csv)
      list.push_back(std::make_unique<DisplacementCsv>());
    return list;
  }

  std::string
  ConstraintCheck::name() const
  {
    return "constraint check";
  }

  void
  ConstraintCheck::execute(const Input &input)
  {
    input.summary.set("interface_jump", input.interface_jump);
    const unsigned int n_not_finite = input.u_not_finite + input.lambda_not_finite;
    input.summary.set("values_not_finite", n_not_finite);
    input.check("values_not_finite",
                "displacements or multipliers that are not finite numbers (overflow?), count",
                n_not_finite,
                0);
  }

  namespace
  {
    /** The master of contact zone @p z for the log: "body 'NAME'" or the rigid obstacle. */
    std::string
    master_name(const Input &input, const unsigned int z)
    {
      const auto &zone = input.parameters.contact.zones[z];
      if (zone.rigid())
        return "(" + zone.obstacle->name() + ")";
      return "body '" + input.bodies[zone.master_body]->parameters.name + "'";
    }
  } // namespace

  std::string
  SmallStrainCheck::name() const
  {
    return "small-strain check";
  }

  std::string
  SmallStrainCheck::note(const Input &input)
  {
    if (input.largest_strain <= limit)
      return "";
    return " with strains up to " + InputParsing::number_text(input.largest_strain) +
           " (outside the small-strain theory that this program solves: are the loads, the "
           "moduli or the prescribed displacements in other units?),";
  }

  void
  SmallStrainCheck::execute(const Input &input)
  {
    input.summary.set("largest_strain", input.largest_strain);
    input.check("largest_strain",
                "a strain outside the small-strain theory that this program solves (linear "
                "elasticity, contact about the initial geometry; are the loads, the moduli or "
                "the prescribed displacements in other units?):",
                input.largest_strain,
                limit);
  }

  std::string
  ContactConditions::name() const
  {
    return "contact conditions";
  }

  void
  ContactConditions::execute(const Input &input)
  {
    const ContactCheck &check = input.contact_check;
    // Inside an obstacle by more than 1 % of the largest displacement.
    input.check("kkt.penetration",
                "a penetration into an obstacle, relative to the largest displacement," +
                  SmallStrainCheck::note(input),
                check.penetration,
                1e-2);
    input.summary.set("kkt", check.json());
    JsonObject totals;
    totals
      .set("normal_force",
           std::vector<double>(check.normal_force.begin_raw(), check.normal_force.end_raw()))
      .set("tangential_force",
           std::vector<double>(check.tangential_force.begin_raw(),
                               check.tangential_force.end_raw()))
      .set("open", check.n_open)
      .set("stick", check.n_stick)
      .set("slip", check.n_slip);
    std::vector<JsonObject> zones;
    for (unsigned int z = 0; z < input.contact_forces.of_zone.size(); ++z)
      {
        const ZoneResultant &r = input.contact_forces.of_zone[z];
        zones.push_back(
          JsonObject()
            .set("zone", z + 1)
            .set("force_on_slave",
                 std::vector<double>(r.on_slave.begin_raw(), r.on_slave.end_raw()))
            .set("force_on_master",
                 std::vector<double>(r.on_master.begin_raw(), r.on_master.end_raw())));
      }
    totals.set("zones", zones);
    input.summary.set("contact", totals);
    input.pcout << "Contact: " << check.n_open << " open, " << check.n_stick << " stick, "
                << check.n_slip << " slip" << std::endl;
    const auto &zone_parameters = input.parameters.contact.zones;
    for (unsigned int z = 0; z < input.contact_forces.of_zone.size(); ++z)
      input.pcout << "  zone " << z + 1 << ": force on the slave body '"
                  << input.bodies[zone_parameters[z].body]->parameters.name << "' "
                  << input.contact_forces.of_zone[z].on_slave << ", on the master "
                  << master_name(input, z) << ' ' << input.contact_forces.of_zone[z].on_master
                  << std::endl;
    input.pcout << "Check: penetration " << check.penetration << ", cone violation "
                << check.cone_violation << ", complementarity " << check.complementarity
                << ", slip angle " << check.slip_angle << std::endl;
    if (check.mortar_overlap)
      report_mortar_overlap(*check.mortar_overlap, input);
  }

  void
  ContactConditions::report_mortar_overlap(const MortarOverlap &overlap, const Input &input)
  {
    input.summary.set("mortar_overlap", overlap.json());
    input.pcout << "Mortar overlap (pointwise, relative to max |u|): slave into master "
                << overlap.slave_into_master << ", master into slave " << overlap.master_into_slave
                << std::endl;
    if (overlap.largest() > mortar_overlap_warning)
      input.pcout << "Warning: the surfaces of a mortar zone overlap pointwise by "
                  << overlap.largest() * 100
                  << "% of the largest displacement (mortar rows hold the gap in the mean over "
                     "each slave node's patch; a finer mesh at the edge of the contact region "
                     "reduces it, doc/contact.md)."
                  << std::endl;
  }

  namespace
  {
    /**
     * The contact nodes of zone 1 of all ranks, in the order of the nodes, with their results:
     * what the Hertz comparison reads of them (position, normal, gap, lumped area, D_kk, λ_N), one
     * zone's
     * worth, gathered from the ranks among which the nodes are split.
     */
    std::pair<std::vector<ContactNode>, std::vector<ContactNodeResult>>
    zone_one_on_every_rank(const Input &input)
    {
      struct Record
      {
        unsigned int number;
        double       x[3], n[3], gap, area, pressure_area, lambda_N;
      };
      std::vector<Record> mine;
      for (unsigned int k = 0; k < input.contact_nodes.size(); ++k)
        {
          const ContactNode &node = input.contact_nodes[k];
          if (node.zone != 0)
            continue;
          Record r{input.contact_layout.node_number(k),
                   {node.x[0], node.x[1], node.x[2]},
                   {node.n[0], node.n[1], node.n[2]},
                   node.gap,
                   node.area,
                   node.pressure_area,
                   input.contact_results[k].lambda_N};
          mine.push_back(r);
        }
      std::vector<Record> all = MPITools::all_gather(input.comm, mine);
      std::sort(all.begin(), all.end(), [](const Record &a, const Record &b) {
        return a.number < b.number;
      });
      std::vector<ContactNode>       nodes(all.size());
      std::vector<ContactNodeResult> results(all.size());
      for (unsigned int k = 0; k < all.size(); ++k)
        {
          nodes[k].zone          = 0;
          nodes[k].x             = Point<3>(all[k].x[0], all[k].x[1], all[k].x[2]);
          nodes[k].n             = Tensor<1, 3>({all[k].n[0], all[k].n[1], all[k].n[2]});
          nodes[k].gap           = all[k].gap;
          nodes[k].area          = all[k].area;
          nodes[k].pressure_area = all[k].pressure_area;
          results[k].lambda_N    = all[k].lambda_N;
        }
      return {std::move(nodes), std::move(results)};
    }
  } // namespace

  std::string
  HertzComparison::name() const
  {
    return "Hertz comparison";
  }

  void
  HertzComparison::execute(const Input &input)
  {
    // A solution that failed the contact check is no contact solution: the comparison would
    // measure the failure (or refuse the scene for it) and hide the check's verdict.
    if (!input.summary.check_failure().empty())
      {
        input.pcout << "Hertz comparison skipped: the solution failed a check." << std::endl;
        return;
      }
    if (Utilities::MPI::n_mpi_processes(input.comm) == 1)
      hertz = compare_with_hertz(input.parameters, input.contact_nodes, input.contact_results);
    else
      {
        const auto [nodes, results] = zone_one_on_every_rank(input);
        hertz                       = compare_with_hertz(input.parameters, nodes, results);
      }
    if (input.pcout.is_active())
      hertz->print(input.pcout.get_stream());
    input.summary.set("hertz", hertz->json());
  }

  std::string
  EquilibriumCheck::name() const
  {
    return "equilibrium check";
  }

  void
  EquilibriumCheck::execute(const Input &input)
  {
    std::vector<JsonObject> body_records;
    double                  worst   = 0;
    const auto              balance = compute_force_balance(input.comm,
                                               input.bodies.size(),
                                               input.owned,
                                               input.u,
                                               input.mapping,
                                               input.contact_forces.on_body);
    for (const auto &body : input.bodies)
      {
        const auto &fb = balance[body->index];
        JsonObject  b;
        b.set("index", body->index + 1).set("name", body->parameters.name);
        b.set("applied_force", std::vector<double>{fb.applied[0], fb.applied[1], fb.applied[2]});
        b.set("support_force", std::vector<double>{fb.support[0], fb.support[1], fb.support[2]});
        b.set("contact_force", std::vector<double>{fb.contact[0], fb.contact[1], fb.contact[2]});
        b.set("force_through", fb.through);
        b.set("relative_imbalance", fb.relative_imbalance);
        body_records.push_back(b);
        worst = std::max(worst, fb.relative_imbalance);
        input.pcout << "Body '" << body->parameters.name << "': applied force " << fb.applied
                    << ", support force " << fb.support << ", contact force " << fb.contact
                    << ", relative imbalance " << fb.relative_imbalance << std::endl;
      }
    input.summary.set(
      "equilibrium",
      JsonObject().set("bodies", body_records).set("largest_relative_imbalance", worst));
    // Gλ = e is restored to rounding after every solve (measured imbalances 1e-16 … 5e-13);
    // the interface jump is the QP's tolerance times the conditioning (measured up to 6e-7).
    input.check("equilibrium.largest_relative_imbalance",
                "a force imbalance of a body (applied + support + contact forces, relative "
                "to the forces that pass through it) of",
                worst,
                1e-6);
    input.check("interface_jump",
                "a jump of the displacements across subdomain interfaces, relative to the "
                "largest displacement, of",
                input.interface_jump,
                1e-2);
  }

  std::string
  MonolithicComparison::name() const
  {
    return "comparison with a monolithic solve";
  }

  void
  MonolithicComparison::execute(const Input &input)
  {
    if (input.contact_layout.n_normal > 0)
      {
        input.pcout << "Comparison with a monolithic solve skipped: it is a linear solve and the "
                       "scene has contact."
                    << std::endl;
        return;
      }
    // The undecomposed bodies are solved on rank 0, which gathers every vertex's displacement;
    // with their cells distributed over the ranks it makes their whole meshes anew.
    auto   vertex_u   = gather_vertex_displacements(input.comm, input.bodies, input.owned, input.u);
    double difference = 0;
    if (input.root())
      {
        double diff2 = 0, norm2 = 0;
        for (const auto &body : input.bodies)
          {
            std::unique_ptr<Body> whole;
            if (body->distributed())
              {
                whole = std::make_unique<Body>(body->parameters, body->index);
                whole->setup();
              }
            const auto mono = solve_monolithic(whole ? *whole : *body, input.mapping, input.fe);
            vertex_u[body->index].resize(mono.size());
            for (unsigned int v = 0; v < mono.size(); ++v)
              {
                diff2 += (mono[v] - vertex_u[body->index][v]).norm_square();
                norm2 += mono[v].norm_square();
              }
          }
        difference = norm2 > 0 ? std::sqrt(diff2 / norm2) : std::sqrt(diff2);
      }
    difference = Utilities::MPI::broadcast(input.comm, difference, 0);
    input.summary.set("monolithic_difference", difference);
    input.pcout << "Relative difference to the monolithic solve: " << difference << std::endl;
  }

  std::string
  ReferenceComparison::name() const
  {
    return "comparison with the reference displacements";
  }

  void
  ReferenceComparison::execute(const Input &input)
  {
    const auto difference = compare_with_reference(
      input.comm, input.owned, input.mapping, input.u, *input.reference_displacements);
    input.summary.set("reference_difference",
                      JsonObject()
                        .set("max_relative", difference.max_relative)
                        .set("energy_relative", difference.energy_relative)
                        .set("vertices", difference.n_vertices));
    input.pcout << "Difference from the reference displacements: " << difference.max_relative
                << " (maximum), " << difference.energy_relative << " (energy norm), relative"
                << std::endl;
  }

  std::string
  ContactOutput::name() const
  {
    return "contact output";
  }

  void
  ContactOutput::execute(const Input &input)
  {
    const ContactOutputShare share(input.first_subdomain,
                                   input.owned,
                                   input.contact_nodes,
                                   input.contact_surfaces.slave,
                                   input.subdomain_owner,
                                   input.comm);
    write_contact_csv(input.result_files,
                      input.comm,
                      input.output_directory,
                      share,
                      input.contact_nodes,
                      input.contact_results);
    if (input.parameters.output.write_vtu)
      write_contact_surface_vtu(input.result_files,
                                input.comm,
                                input.output_directory,
                                share,
                                input.contact_nodes,
                                input.contact_results,
                                input.contact_surfaces.slave,
                                input.first_subdomain,
                                input.subdomain_owner,
                                input.comm);
  }

  std::string
  FclibExport::name() const
  {
    return "FCLIB export";
  }

  namespace
  {
    /** A contact node's key (zone, body, vertex) and its result, as numbers to gather. */
    constexpr unsigned int values_per_node = 10;

    std::vector<double>
    keyed_results(const std::vector<ContactNode>       &nodes,
                  const std::vector<ContactNodeResult> &results)
    {
      std::vector<double> values;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        {
          const ContactNodeResult &r = results[k];
          values.insert(values.end(),
                        {double(nodes[k].zone),
                         double(nodes[k].body),
                         double(nodes[k].vertex),
                         r.lambda_N,
                         r.lambda_T[0],
                         r.lambda_T[1],
                         r.gap,
                         r.slip[0],
                         r.slip[1],
                         double(static_cast<int>(r.status))});
        }
      return values;
    }

    /**
     * The whole scene on rank 0 for the FCLIB export: the bodies' whole meshes (made anew when
     * their cells are distributed), every contact node (searched anew on them: the nodes of the
     * ranks' home vertices together) and the result of each, gathered from the rank that holds
     * it. On one rank the run's own.
     */
    struct WholeContact
    {
      std::vector<std::unique_ptr<Body>>        made_bodies;
      std::vector<ContactNode>                  made_nodes;
      std::vector<ContactNodeResult>            made_results;
      const std::vector<std::unique_ptr<Body>> *bodies  = nullptr;
      const std::vector<ContactNode>           *nodes   = nullptr;
      const std::vector<ContactNodeResult>     *results = nullptr;
    };

    /** On rank 0, from the keyed results of every rank (@p gathered). */
    WholeContact
    whole_contact(const Input &input, const std::vector<std::vector<double>> &gathered)
    {
      WholeContact whole{{}, {}, {}, &input.bodies, &input.contact_nodes, &input.contact_results};
      if (Utilities::MPI::n_mpi_processes(input.comm) == 1)
        return whole;
      for (const auto &body : input.bodies)
        {
          whole.made_bodies.push_back(std::make_unique<Body>(body->parameters, body->index));
          whole.made_bodies.back()->setup();
        }
      whole.made_nodes = find_contact_nodes(whole.made_bodies, input.parameters.contact);
      std::map<std::array<unsigned int, 3>, ContactNodeResult> result_of;
      for (const auto &values : gathered)
        for (std::size_t j = 0; j + values_per_node <= values.size(); j += values_per_node)
          {
            const double *v = values.data() + j;
            result_of[{{unsigned(v[0]), unsigned(v[1]), unsigned(v[2])}}] =
              ContactNodeResult{v[3], {v[4], v[5]}, v[6], {v[7], v[8]}, ContactStatus(int(v[9]))};
          }
      AssertThrow(result_of.size() == whole.made_nodes.size(),
                  ExcMessage("FCLIB export: the ranks hold " + std::to_string(result_of.size()) +
                             " contact nodes, the whole meshes have " +
                             std::to_string(whole.made_nodes.size()) + "."));
      for (const ContactNode &node : whole.made_nodes)
        whole.made_results.push_back(result_of.at({{node.zone, node.body, node.vertex}}));
      whole.bodies  = &whole.made_bodies;
      whole.nodes   = &whole.made_nodes;
      whole.results = &whole.made_results;
      return whole;
    }
  } // namespace

  void
  FclibExport::execute(const Input &input)
  {
    // The undecomposed bodies are assembled on rank 0, which gathers every vertex's displacement
    // and every contact node's result.
    const auto vertex_u =
      gather_vertex_displacements(input.comm, input.bodies, input.owned, input.u);
    const auto gathered =
      Utilities::MPI::gather(input.comm,
                             keyed_results(input.contact_nodes, input.contact_results),
                             0);
    input.on_all_ranks([&]() {
      if (!input.root())
        return;
      const WholeContact whole = whole_contact(input, gathered);
      std::string        title = "feticontact:";
      for (const auto &body : input.bodies)
        title += (body->index > 0 ? ", " : " ") + body->parameters.name;
      const std::string file =
        input.result_files.reserve(input.output_directory + "/fclib_problem.hdf5");
      const FclibProblem problem = assemble_fclib_problem(*whole.bodies,
                                                          *whole.nodes,
                                                          *whole.results,
                                                          vertex_u,
                                                          input.mapping,
                                                          input.fe,
                                                          input.parameters.output.fclib_units);
      try
        {
          write_fclib(file,
                      problem,
                      title,
                      "P1 tetrahedral elasticity, Coulomb friction; v, u: displacements, "
                      "r: forces (λ_N, λ_T1, λ_T2) in the frames [n, t1, t2].");
        }
      catch (const std::runtime_error &e)
        {
          throw OutputError("Cannot write the output file <" + input.output_directory +
                            "/fclib_problem.hdf5>: " + e.what());
        }
    });
  }

  std::string
  SolutionOutput::name() const
  {
    return "solution output";
  }

  void
  SolutionOutput::execute(const Input &input)
  {
    input.on_all_ranks([&]() {
      write_solution_vtu(input.result_files,
                         input.comm,
                         input.owned,
                         input.u,
                         input.first_subdomain.back(),
                         input.mapping,
                         input.output_directory);
    });
  }

  std::string
  DisplacementCsv::name() const
  {
    return "displacement CSV";
  }

  void
  DisplacementCsv::execute(const Input &input)
  {
    // This rank's rows: its subdomains in increasing order, each with the vertices whose lowest
    // copy it holds, by vertex number (the ranks hold consecutive ranges of subdomains, so the
    // file is the same on any number of ranks).
    std::vector<unsigned int> order(input.owned.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](const unsigned int a, const unsigned int b) {
      return input.owned[a]->global_index < input.owned[b]->global_index;
    });
    std::ostringstream rows;
    if (input.root())
      rows << "body,x,y,z,ux,uy,uz\n";
    rows << std::setprecision(17);
    for (const unsigned int i : order)
      {
        const Subdomain &s = *input.owned[i];
        for (const auto &[w, v] : s.reported_vertices())
          {
            const auto &x = s.mesh.get_vertices()[v];
            rows << s.body.index + 1 << ',' << x[0] << ',' << x[1] << ',' << x[2];
            for (unsigned int c = 0; c < 3; ++c)
              rows << ',' << input.u[i][s.vertex_dofs[v][c]];
            rows << '\n';
          }
      }
    input.result_files.write_collectively(input.comm,
                                          input.output_directory + "/displacements.csv",
                                          rows.str());
  }
} // namespace FetiContact::Postprocessing
