#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/postprocessing/contact_output.h>
#include <feticontact/scene/decomposition.h>

#include <algorithm>
#include <array>
#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>
#include <cstdio>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    std::string
    piece_name(const unsigned int subdomain)
    {
      char name[64];
      std::snprintf(name, sizeof(name), "contact_surface_%04u.vtu", subdomain);
      return name;
    }

    /** A point array of the contact surface: its name and number of components. */
    struct Field
    {
      const char  *name;
      unsigned int components;
    };
    constexpr std::array<Field, 9> fields{{{"normal_force", 1},
                                           {"pressure", 1},
                                           {"tangential_force", 3},
                                           {"contact_force", 3},
                                           {"gap", 1},
                                           {"slip", 3},
                                           {"status", 1},
                                           {"zone", 1},
                                           {"D_kk", 1}}};

    /** The values of every field at contact node k, in the order of `fields`. */
    std::vector<double>
    node_values(const ContactNode &node, const ContactNodeResult &r)
    {
      const Tensor<1, 3> tangential = -(r.lambda_T[0] * node.t1 + r.lambda_T[1] * node.t2);
      const Tensor<1, 3> force      = -r.lambda_N * node.n + tangential;
      const Tensor<1, 3> slip       = r.slip[0] * node.t1 + r.slip[1] * node.t2;
      return {r.lambda_N,
              r.lambda_N / node.pressure_area,
              tangential[0],
              tangential[1],
              tangential[2],
              force[0],
              force[1],
              force[2],
              r.gap,
              slip[0],
              slip[1],
              slip[2],
              static_cast<double>(static_cast<int>(r.status)),
              static_cast<double>(node.zone + 1),
              node.pressure_area};
    }

    /** The values of a surface vertex that is not a contact node: zeros, status −1. */
    std::vector<double>
    no_node_values()
    {
      std::vector<double> values;
      for (const Field &field : fields)
        values.insert(values.end(), field.components, std::string(field.name) == "status" ? -1 : 0);
      return values;
    }

    using PointKey = std::array<unsigned int, 3>; // zone, body, vertex
    /** The values at points of a piece whose contact nodes other ranks hold. */
    using PointValues = std::map<PointKey, std::vector<double>>;

    // Written by hand, not by DataOut on a Triangulation<2,3> of the contact faces: DataOut writes
    // every cell's vertices as points of their own (a contact node would be up to six points
    // with its values repeated), and deal.II 9.4.1 built with zlib (Debian 12) writes VTU data
    // arrays as compressed base64 with no plain-text option (VtkFlags::ZlibCompressionLevel
    // only). A piece has one point per (zone, vertex) of its triangles with the node's values in
    // plain text, which tests/run_case.py --check-contact-vtu compares node by node with
    // contact.csv; a node on the faces of two subdomains is a point of both pieces.
    std::string
    piece_vtu(const std::map<PointKey, unsigned int> &node_at,
              const PointValues                      &elsewhere,
              const std::vector<ContactNode>         &nodes,
              const std::vector<ContactNodeResult>   &results,
              const std::vector<ContactTriangle>     &triangles,
              const std::vector<unsigned int>        &which,
              const unsigned int                      subdomain,
              const std::map<PointKey, unsigned int> &point_owner)
    {
      // Points: the distinct (zone, body, vertex) of the triangles; a vertex on the surfaces of
      // two zones (an edge where two obstacles meet) is a point of each zone's patch, with that
      // zone's contact data.
      std::map<PointKey, unsigned int> point_of;
      std::vector<PointKey>            points;
      std::vector<Point<3>>            positions;
      for (const unsigned int t : which)
        for (unsigned int i = 0; i < 3; ++i)
          {
            const PointKey key{{triangles[t].zone, triangles[t].body, triangles[t].vertices[i]}};
            if (point_of.emplace(key, points.size()).second)
              {
                points.push_back(key);
                positions.push_back(triangles[t].points[i]);
              }
          }

      std::ostringstream out;
      out << std::setprecision(10);
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
             "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
          << points.size() << "\" NumberOfCells=\"" << which.size() << "\">\n";
      out << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (const auto &x : positions)
        out << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
      out << "</DataArray></Points>\n<Cells>\n"
             "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
      for (const unsigned int t : which)
        {
          const auto &c = triangles[t];
          out << point_of[{{c.zone, c.body, c.vertices[0]}}] << ' '
              << point_of[{{c.zone, c.body, c.vertices[1]}}] << ' '
              << point_of[{{c.zone, c.body, c.vertices[2]}}] << '\n';
        }
      out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
      for (unsigned int c = 0; c < which.size(); ++c)
        out << 3 * (c + 1) << '\n';
      out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
      for (unsigned int c = 0; c < which.size(); ++c)
        out << "5\n"; // VTK_TRIANGLE
      out << "</DataArray>\n</Cells>\n<PointData Scalars=\"normal_force\">\n";

      std::vector<std::vector<double>> values(points.size());
      for (unsigned int p = 0; p < points.size(); ++p)
        {
          const auto it    = node_at.find(points[p]);
          const auto other = elsewhere.find(points[p]);
          values[p] = it != node_at.end() ? node_values(nodes[it->second], results[it->second]) :
                      other != elsewhere.end() ? other->second :
                                                 no_node_values();
        }
      unsigned int first = 0;
      for (const Field &field : fields)
        {
          out << "<DataArray type=\"Float64\" Name=\"" << field.name << '"';
          if (field.components > 1)
            out << " NumberOfComponents=\"" << field.components << '"';
          out << " format=\"ascii\">\n";
          for (const auto &v : values)
            for (unsigned int c = 0; c < field.components; ++c)
              out << v[first + c] << (c + 1 < field.components ? ' ' : '\n');
          out << "</DataArray>\n";
          first += field.components;
        }
      // vtkDataSetAttributes::DUPLICATEPOINT (1): a point that another piece holds as its own.
      out << "<DataArray type=\"UInt8\" Name=\"vtkGhostType\" format=\"ascii\">\n";
      for (const PointKey &p : points)
        out << (point_owner.at(p) == subdomain ? 0 : 1) << '\n';
      out << "</DataArray>\n";
      out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
      return out.str();
    }

    /**
     * The values of the points of this rank's pieces (@p share) whose contact nodes other ranks
     * hold: each point is asked of the rank of its home subdomain, which answers with the values
     * of its node there or no_node_values(), point to point between the ranks that share surface
     * vertices (Utilities::MPI::some_to_some). Collective over @p node_comm.
     */
    PointValues
    values_held_elsewhere(const ContactOutputShare               &share,
                          const std::vector<ContactTriangle>     &triangles,
                          const std::map<PointKey, unsigned int> &node_at,
                          const std::vector<ContactNode>         &nodes,
                          const std::vector<ContactNodeResult>   &results,
                          const std::vector<unsigned int>        &first_subdomain,
                          const std::vector<unsigned int>        &subdomain_owner,
                          const MPI_Comm                          node_comm)
    {
      if (Utilities::MPI::n_mpi_processes(node_comm) == 1)
        return {}; // every node here
      const unsigned int rank = Utilities::MPI::this_mpi_process(node_comm);
      // The keys asked of each rank (zone, body, vertex, flattened), in increasing order.
      std::map<unsigned int, std::set<PointKey>> wanted;
      for (const auto &list : share.triangles)
        for (const unsigned int t : list)
          for (unsigned int i = 0; i < 3; ++i)
            {
              const ContactTriangle &c    = triangles[t];
              const PointKey         key  = {{c.zone, c.body, c.vertices[i]}};
              const unsigned int     home = subdomain_owner[first_subdomain[c.body] + c.home[i]];
              if (home != rank && node_at.count(key) == 0)
                wanted[home].insert(key);
            }
      std::map<unsigned int, std::vector<unsigned int>> asking;
      for (const auto &[r, keys] : wanted)
        for (const PointKey &key : keys)
          asking[r].insert(asking[r].end(), key.begin(), key.end());
      // The answers in the order of the keys asked.
      std::map<unsigned int, std::vector<double>> answer;
      for (const auto &[r, keys] : Utilities::MPI::some_to_some(node_comm, asking))
        for (unsigned int j = 0; j + 2 < keys.size(); j += 3)
          {
            const auto it = node_at.find(PointKey{{keys[j], keys[j + 1], keys[j + 2]}});
            const std::vector<double> v = it != node_at.end() ?
                                            node_values(nodes[it->second], results[it->second]) :
                                            no_node_values();
            answer[r].insert(answer[r].end(), v.begin(), v.end());
          }
      const unsigned int n_values = no_node_values().size();
      PointValues        values;
      for (const auto &[r, answered] : Utilities::MPI::some_to_some(node_comm, answer))
        {
          unsigned int j = 0;
          for (const PointKey &key : wanted.at(r))
            {
              values[key].assign(answered.begin() + j, answered.begin() + j + n_values);
              j += n_values;
            }
        }
      return values;
    }

    /** The parallel record: the fields of the pieces and the pieces' file names. */
    std::string
    pvtu_record(const std::vector<unsigned int> &subdomains)
    {
      std::ostringstream out;
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" "
             "byte_order=\"LittleEndian\">\n<PUnstructuredGrid GhostLevel=\"0\">\n"
             "<PPointData Scalars=\"normal_force\">\n";
      for (const Field &field : fields)
        out << "<PDataArray type=\"Float64\" Name=\"" << field.name << "\" NumberOfComponents=\""
            << field.components << "\"/>\n";
      out << "<PDataArray type=\"UInt8\" Name=\"vtkGhostType\" NumberOfComponents=\"1\"/>\n";
      out << "</PPointData>\n<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>"
             "</PPoints>\n";
      for (const unsigned int s : subdomains)
        out << "<Piece Source=\"" << piece_name(s) << "\"/>\n";
      out << "</PUnstructuredGrid>\n</VTKFile>\n";
      return out.str();
    }
  } // namespace

  ContactOutputShare::ContactOutputShare(const std::vector<unsigned int>    &first_subdomain,
                                         const std::vector<Subdomain *>     &owned,
                                         const std::vector<ContactNode>     &contact_nodes,
                                         const std::vector<ContactTriangle> &contact_triangles,
                                         const std::vector<unsigned int>    &subdomain_owner,
                                         const MPI_Comm                      comm)
  {
    std::vector<unsigned int> mine;
    for (const Subdomain *s : owned)
      mine.push_back(s->global_index);
    std::sort(mine.begin(), mine.end());
    const auto is_mine = [&](const unsigned int s) {
      return std::binary_search(mine.begin(), mine.end(), s);
    };

    std::vector<std::pair<unsigned int, unsigned int>> node_subdomain; // (subdomain, node)
    for (unsigned int k = 0; k < contact_nodes.size(); ++k)
      {
        const auto        &node = contact_nodes[k];
        const unsigned int s    = first_subdomain[node.body] + node.copies.parts.front();
        if (is_mine(s))
          node_subdomain.emplace_back(s, k);
      }
    std::sort(node_subdomain.begin(), node_subdomain.end());
    for (const auto &[s, k] : node_subdomain)
      nodes.push_back(k);

    std::map<unsigned int, std::vector<unsigned int>> of_subdomain;
    std::vector<unsigned int>                         subdomain_of(contact_triangles.size());
    for (unsigned int t = 0; t < contact_triangles.size(); ++t)
      {
        const auto &triangle = contact_triangles[t];
        subdomain_of[t]      = first_subdomain[triangle.body] + triangle.part;
        if (is_mine(subdomain_of[t]))
          {
            of_subdomain[subdomain_of[t]].push_back(t);
            for (const unsigned int v : triangle.vertices)
              point_owner.emplace(PointKey{{triangle.zone, triangle.body, v}}, subdomain_of[t]);
          }
      }
    for (unsigned int t = 0; t < contact_triangles.size(); ++t)
      for (const unsigned int v : contact_triangles[t].vertices)
        {
          const auto it =
            point_owner.find(PointKey{{contact_triangles[t].zone, contact_triangles[t].body, v}});
          if (it != point_owner.end())
            it->second = std::min(it->second, subdomain_of[t]);
        }
    for (auto &[s, list] : of_subdomain)
      {
        subdomains.push_back(s);
        triangles.push_back(std::move(list));
      }
    lowest_over_ranks(first_subdomain, contact_triangles, subdomain_owner, comm);
  }

  void
  ContactOutputShare::lowest_over_ranks(const std::vector<unsigned int>    &first_subdomain,
                                        const std::vector<ContactTriangle> &contact_triangles,
                                        const std::vector<unsigned int>    &subdomain_owner,
                                        const MPI_Comm                      comm)
  {
    // Every point's lowest subdomain here to the rank of its home subdomain, which answers with
    // the lowest of all ranks.
    std::map<PointKey, unsigned int> home_rank;
    for (const ContactTriangle &t : contact_triangles)
      for (unsigned int i = 0; i < 3; ++i)
        home_rank.emplace(PointKey{{t.zone, t.body, t.vertices[i]}},
                          subdomain_owner[first_subdomain[t.body] + t.home[i]]);
    std::map<unsigned int, std::vector<std::array<unsigned int, 4>>> questions;
    for (const auto &[p, s] : point_owner)
      questions[home_rank.at(p)].push_back({{p[0], p[1], p[2], s}});
    const auto                       asked = Utilities::MPI::some_to_some(comm, questions);
    std::map<PointKey, unsigned int> lowest;
    for (const auto &[from, list] : asked)
      for (const auto &[zone, body, vertex, s] : list)
        {
          const auto [entry, first_seen] = lowest.emplace(PointKey{{zone, body, vertex}}, s);
          if (!first_seen)
            entry->second = std::min(entry->second, s);
        }
    std::map<unsigned int, std::vector<std::array<unsigned int, 4>>> answers;
    for (const auto &[from, list] : asked)
      for (const auto &q : list)
        answers[from].push_back({{q[0], q[1], q[2], lowest.at(PointKey{{q[0], q[1], q[2]}})}});
    for (const auto &[from, list] : Utilities::MPI::some_to_some(comm, answers))
      for (const auto &[zone, body, vertex, s] : list)
        point_owner.at(PointKey{{zone, body, vertex}}) = s;
  }

  void
  write_contact_csv(ResultFiles                          &files,
                    const MPI_Comm                        comm,
                    const std::string                    &directory,
                    const ContactOutputShare             &share,
                    const std::vector<ContactNode>       &nodes,
                    const std::vector<ContactNodeResult> &results)
  {
    std::ostringstream rows;
    write_contact_csv(
      rows, nodes, results, share.nodes, Utilities::MPI::this_mpi_process(comm) == 0);
    files.write_collectively(comm, directory + "/contact.csv", rows.str());
  }

  void
  write_contact_surface_vtu(ResultFiles                          &files,
                            const MPI_Comm                        comm,
                            const std::string                    &directory,
                            const ContactOutputShare             &share,
                            const std::vector<ContactNode>       &nodes,
                            const std::vector<ContactNodeResult> &results,
                            const std::vector<ContactTriangle>   &triangles,
                            const std::vector<unsigned int>      &first_subdomain,
                            const std::vector<unsigned int>      &subdomain_owner,
                            const MPI_Comm                        node_comm)
  {
    std::map<PointKey, unsigned int> node_at;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      node_at.emplace(PointKey{{nodes[k].zone, nodes[k].body, nodes[k].vertex}}, k);
    const PointValues elsewhere = values_held_elsewhere(
      share, triangles, node_at, nodes, results, first_subdomain, subdomain_owner, node_comm);
    const auto                pieces = Utilities::MPI::gather(comm, share.subdomains, 0);
    std::vector<unsigned int> all;
    for (const auto &p : pieces)
      all.insert(all.end(), p.begin(), p.end());
    std::sort(all.begin(), all.end());

    MPITools::collectively<OutputError>(comm, [&]() {
      for (unsigned int i = 0; i < share.subdomains.size(); ++i)
        {
          const std::string text = piece_vtu(node_at,
                                             elsewhere,
                                             nodes,
                                             results,
                                             triangles,
                                             share.triangles[i],
                                             share.subdomains[i],
                                             share.point_owner);
          files.write(directory + "/" + piece_name(share.subdomains[i]),
                      [&](std::ostream &out) { out << text; });
        }
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        {
          files.write(directory + "/contact_surface.pvtu",
                      [&](std::ostream &out) { out << pvtu_record(all); });
          files.write(directory + "/contact_surface.pvd", [](std::ostream &pvd) {
            DataOutBase::write_pvd_record(pvd, {{0.0, "contact_surface.pvtu"}});
          });
        }
    });
  }
} // namespace FetiContact
