// The contact search shared among the ranks (find_contact_nodes with home_nodes = true, the
// bodies' cells distributed): every rank must find the nodes of its home vertices, those whose
// lowest part it holds, and they must be the nodes that the whole search (every rank gathers
// the whole surfaces) finds at those vertices, to the bit, in the same order, with their keepers;
// the zone reports must be those of the whole search, and every triangle of the zones' surfaces
// must be listed by one rank. The parts go to the ranks in a scrambled order, so that a rank's
// faces are not a slab. Run on the parameter files given as arguments (rigid planes, spheres and
// cylinders, node to node, mortar with folds, zones sharing edges), on 3 ranks. A scene
// whose plane cuts the body at one rank's nodes only must be refused on every rank. Two blocks
// node to node across a gap of several mean edges: the master faces a rank gets must grow.

#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/scene/body.h>

#include "test_tools.h"

#include <filesystem>
#include <memory>

using namespace dealii;
using namespace FetiContact;

namespace
{
  /** The bodies of @p scene, their parts on the ranks of @p comm in a scrambled order. */
  std::vector<std::unique_ptr<Body>>
  distributed_bodies(const Parameters::Scene &scene, const MPI_Comm comm)
  {
    const unsigned int                 n_ranks = Utilities::MPI::n_mpi_processes(comm);
    std::vector<std::unique_ptr<Body>> bodies;
    for (unsigned int b = 0; b < scene.bodies.size(); ++b)
      {
        bodies.push_back(std::make_unique<Body>(scene.bodies[b], b));
        bodies.back()->create_and_partition(comm);
        bodies.back()->distribute(
          [&](const unsigned int part) { return (5 * part + b + 1) % n_ranks; });
        bodies.back()->set_up_boundary();
      }
    return bodies;
  }

  bool
  same(const VertexCopies &a, const VertexCopies &b)
  {
    return a.parts == b.parts && a.prescribed == b.prescribed;
  }

  /** Whether @p a and @p b are the same node, to the bit (keepers compared by the caller). */
  bool
  same(const ContactNode &a, const ContactNode &b)
  {
    bool equal = a.zone == b.zone && a.body == b.body && a.vertex == b.vertex && a.x == b.x &&
                 same(a.copies, b.copies) && a.n == b.n && a.t1 == b.t1 && a.t2 == b.t2 &&
                 a.gap == b.gap && a.friction == b.friction && a.area == b.area &&
                 a.pressure_area == b.pressure_area && a.mortar == b.mortar &&
                 a.master.size() == b.master.size() && a.keeper.has_value() == b.keeper.has_value();
    for (unsigned int j = 0; equal && j < a.master.size(); ++j)
      equal = a.master[j] == b.master[j] && a.master[j].y == b.master[j].y &&
              same(a.master[j].copies, b.master[j].copies);
    return equal;
  }

  bool
  same(const ZoneReport &a, const ZoneReport &b)
  {
    return a.discretization == b.discretization && a.n_nodes == b.n_nodes &&
           a.n_uncovered == b.n_uncovered && a.n_partly_covered == b.n_partly_covered &&
           a.n_overlapping == b.n_overlapping && a.search_distance == b.search_distance &&
           a.n_segments == b.n_segments;
  }

  /** The scene of @p file with @p overrides (as --set gives them). */
  Parameters::Scene
  read_scene(const std::string &file, const std::vector<std::string> &overrides)
  {
    ParameterHandler  prm;
    Parameters::Scene scene;
    scene.parse_parameters(prm, Parameters::Scene::read_parameter_file(prm, file, overrides));
    return scene;
  }

  /**
   * The shared search of @p file against the whole search, on the ranks of @p comm, with the
   * bodies' own decompositions or, with @p parts > 0, every body cut into that many METIS parts
   * (irregular parts, whose interfaces cross the contact surfaces anywhere).
   */
  void
  check_scene(const std::string              &file,
              const MPI_Comm                  comm,
              const unsigned int              parts,
              const std::vector<std::string> &changes = {},
              const std::string              &what    = "")
  {
    const unsigned int       rank      = Utilities::MPI::this_mpi_process(comm);
    std::vector<std::string> overrides = changes;
    if (parts > 0)
      for (unsigned int b = 1; b <= read_scene(file, {}).bodies.size(); ++b)
        {
          const std::string body = "Body " + std::to_string(b) + "/Decomposition/";
          overrides.push_back(body + "Method=metis");
          overrides.push_back(body + "Number of parts=" + std::to_string(parts));
        }
    const Parameters::Scene scene  = read_scene(file, overrides);
    const auto              bodies = distributed_bodies(scene, comm);
    ContactSurfaces         whole_surfaces, home_surfaces;
    std::vector<ZoneReport> whole_reports, home_reports;
    const auto              whole =
      find_contact_nodes(bodies, scene.contact, &whole_surfaces, &whole_reports, false);
    const auto home =
      find_contact_nodes(bodies, scene.contact, &home_surfaces, &home_reports, true);

    // The whole search's nodes at this rank's home vertices, keepers renumbered to them.
    std::vector<unsigned int> index_of(whole.size(), numbers::invalid_unsigned_int);
    std::vector<ContactNode>  expected;
    for (unsigned int k = 0; k < whole.size(); ++k)
      if (bodies[whole[k].body]->rank_of_part(whole[k].copies.parts.front()) == rank)
        {
          index_of[k] = expected.size();
          expected.push_back(whole[k]);
        }
    bool same_nodes = expected.size() == home.size();
    for (unsigned int k = 0; same_nodes && k < home.size(); ++k)
      same_nodes = same(home[k], expected[k]) &&
                   (!home[k].keeper || index_of.at(*expected[k].keeper) == *home[k].keeper);
    // The first node that differs, for the log of a failed check.
    for (unsigned int k = 0; k < home.size() && k < expected.size(); ++k)
      if (!same(home[k], expected[k]))
        {
          const ContactNode &a = home[k], &b = expected[k];
          std::cout << "  rank " << rank << ", node " << k << " at vertex " << a.vertex << " ("
                    << b.vertex << "): gap " << sci(a.gap - b.gap) << ", normal "
                    << sci((a.n - b.n).norm()) << ", area " << sci(a.area - b.area) << ", D_kk "
                    << sci(a.pressure_area - b.pressure_area) << ", " << a.master.size() << " ("
                    << b.master.size() << ") master vertices" << std::endl;
          break;
        }
    bool same_reports = home_reports.size() == whole_reports.size();
    for (unsigned int z = 0; same_reports && z < home_reports.size(); ++z)
      same_reports = same(home_reports[z], whole_reports[z]);
    const std::string name =
      std::filesystem::path(file).filename().string() +
      (parts > 0 ? " in " + std::to_string(parts) + " METIS parts per body" : "") + what + " on " +
      std::to_string(Utilities::MPI::n_mpi_processes(comm)) + " rank(s)";
    const unsigned int n_home = Utilities::MPI::sum(static_cast<unsigned int>(home.size()), comm);
    check(Utilities::MPI::min(same_nodes ? 1u : 0u, comm) == 1 && n_home == whole.size(),
          name + ": the home nodes of every rank are the whole search's, to the bit (" +
            std::to_string(n_home) + " of " + std::to_string(whole.size()) + " nodes)");
    check(Utilities::MPI::min(same_reports ? 1u : 0u, comm) == 1,
          name + ": the zone reports are the whole search's");
    const auto n_listed = [&](const std::vector<ContactTriangle> &list) {
      return Utilities::MPI::sum(static_cast<unsigned int>(list.size()), comm);
    };
    check(n_listed(home_surfaces.slave) == n_listed(whole_surfaces.slave) &&
            n_listed(home_surfaces.master) == n_listed(whole_surfaces.master),
          name + ": every surface triangle is listed by one rank (" +
            std::to_string(n_listed(home_surfaces.slave)) + " slave, " +
            std::to_string(n_listed(home_surfaces.master)) + " master)");
  }

  /**
   * The brick on a plane that cuts it at one end only (the nodes there lie inside the obstacle):
   * the shared search must refuse it on every rank, with the whole search's message.
   */
  void
  check_refused(const MPI_Comm comm)
  {
    std::string text = brick_text("set Method = blocks\nset Blocks = 4, 1, 1");
    text += "subsection Contact\n set Number of zones = 1\n subsection Zone 1\n"
            "  set Type = rigid plane\n  set Body = 1\n  set Surface = z = zmin\n"
            "  set Plane point = 2.5, 0, 0\n  set Plane normal = -0.05, 0, 1\n end\nend\n";
    dealii::ParameterHandler prm;
    Parameters::Scene::declare_parameters(prm, 1, 1);
    prm.parse_input_from_string(text);
    Parameters::Scene scene;
    scene.parse_parameters(prm);
    const auto bodies  = distributed_bodies(scene, comm);
    const auto refusal = [&](const bool home_nodes) {
      try
        {
          find_contact_nodes(bodies, scene.contact, nullptr, nullptr, home_nodes);
        }
      catch (const InputError &e)
        {
          return std::string(e.what());
        }
      return std::string();
    };
    const std::string message = refusal(true);
    const bool refused = message.find("lies inside the rigid obstacle") != std::string::npos &&
                         message == refusal(false);
    check(Utilities::MPI::min(refused ? 1u : 0u, comm) == 1,
          "a plane through one end of the brick is refused on every rank: " + message);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (int i = 1; i < argc; ++i)
    {
      for (const unsigned int parts : {0u, 7u})
        check_scene(argv[i], MPI_COMM_WORLD, parts);
      // Node to node across a gap of a few mean edges: the master faces sent must grow.
      if (std::filesystem::path(argv[i]).filename() == "two_blocks.prm")
        check_scene(argv[i],
                    MPI_COMM_WORLD,
                    7,
                    {"Body 2/Mesh/Lower corner=0.5, 0, 0.8",
                     "Body 2/Mesh/Upper corner=1.5, 1, 1.3",
                     "Contact/Zone 2/Discretization=node to node"},
                    ", node to node across a gap of 0.3 m");
    }
  check_refused(MPI_COMM_WORLD);
  return n_failures;
}
