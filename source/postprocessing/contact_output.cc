#include <deal.II/base/data_out_base.h>

#include <feticontact/postprocessing/contact_output.h>

#include <array>
#include <fstream>
#include <iomanip>
#include <map>

namespace FetiContact
{
  using namespace dealii;

  // Written by hand, not by DataOut on a Triangulation<2,3> of the contact faces: DataOut writes
  // every cell's vertices as points of their own (a contact node would be up to six points with
  // its values repeated), and deal.II 9.4.1 built with zlib (Debian 12) writes VTU data arrays
  // as compressed base64 with no plain-text option (VtkFlags::ZlibCompressionLevel only). This
  // file has one point per (zone, vertex) with the node's values in plain text, which
  // tests/run_case.py --check-contact-vtu compares node by node with contact.csv. Its cost is
  // small: at k = 16 (prm/brick_contact.prm, Subdivisions 48, 16, 16; 816 contact nodes, a file
  // of 159 kB) the whole output phase, solution VTU and checks included, took 0.62 s (median of
  // 3 runs of 5.5 to 6.9 s).
  void
  write_contact_surface_vtu(ResultFiles                              &files,
                            const std::string                        &directory,
                            const std::vector<std::unique_ptr<Body>> &bodies,
                            const std::vector<ContactNode>           &nodes,
                            const std::vector<ContactNodeResult>     &results,
                            const std::vector<ContactTriangle>       &triangles)
  {
    // Points: the distinct (zone, body, vertex) of the triangles; a vertex on the surfaces of
    // two zones (an edge where two obstacles meet) is a point of each zone's patch, with that
    // zone's contact data.
    using PointKey = std::array<unsigned int, 3>;
    std::map<PointKey, unsigned int> point_of;
    std::vector<PointKey>            points;
    for (const auto &t : triangles)
      for (const unsigned int v : t.vertices)
        if (point_of.emplace(PointKey{{t.zone, t.body, v}}, points.size()).second)
          points.push_back({{t.zone, t.body, v}});
    std::vector<int> node_of(points.size(), -1);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const auto it = point_of.find({{nodes[k].zone, nodes[k].body, nodes[k].vertex}});
        if (it != point_of.end())
          node_of[it->second] = k;
      }

    std::ostream &out = files.open(directory + "/contact_surface.vtu");
    out << std::setprecision(10);
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
        << points.size() << "\" NumberOfCells=\"" << triangles.size() << "\">\n";
    out << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto &[z, b, v] : points)
      {
        const auto &x = bodies[b]->mesh.get_vertices()[v];
        out << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
      }
    out << "</DataArray></Points>\n<Cells>\n"
           "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const auto &t : triangles)
      out << point_of[{{t.zone, t.body, t.vertices[0]}}] << ' '
          << point_of[{{t.zone, t.body, t.vertices[1]}}] << ' '
          << point_of[{{t.zone, t.body, t.vertices[2]}}] << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (unsigned int c = 0; c < triangles.size(); ++c)
      out << 3 * (c + 1) << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (unsigned int c = 0; c < triangles.size(); ++c)
      out << "5\n"; // VTK_TRIANGLE
    out << "</DataArray>\n</Cells>\n<PointData Scalars=\"normal_force\">\n";

    const auto scalar = [&](const std::string &name, const auto &value) {
      out << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (unsigned int p = 0; p < points.size(); ++p)
        out << (node_of[p] < 0 ? 0.0 : double(value(node_of[p]))) << '\n';
      out << "</DataArray>\n";
    };
    const auto vector = [&](const std::string &name, const auto &value) {
      out << "<DataArray type=\"Float64\" Name=\"" << name
          << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (unsigned int p = 0; p < points.size(); ++p)
        {
          const Tensor<1, 3> v = node_of[p] < 0 ? Tensor<1, 3>() : value(node_of[p]);
          out << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
        }
      out << "</DataArray>\n";
    };
    scalar("normal_force", [&](int k) { return results[k].lambda_N; });
    scalar("pressure", [&](int k) { return results[k].lambda_N / nodes[k].pressure_area; });
    const auto tangential = [&](int k) {
      return Tensor<1, 3>(
        -(results[k].lambda_T[0] * nodes[k].t1 + results[k].lambda_T[1] * nodes[k].t2));
    };
    vector("tangential_force", tangential);
    vector("contact_force",
           [&](int k) { return Tensor<1, 3>(-results[k].lambda_N * nodes[k].n + tangential(k)); });
    scalar("gap", [&](int k) { return results[k].gap; });
    vector("slip", [&](int k) {
      return Tensor<1, 3>(results[k].slip[0] * nodes[k].t1 + results[k].slip[1] * nodes[k].t2);
    });
    out << "<DataArray type=\"Float64\" Name=\"status\" format=\"ascii\">\n";
    for (unsigned int p = 0; p < points.size(); ++p)
      out << (node_of[p] < 0 ? -1 : static_cast<int>(results[node_of[p]].status)) << '\n';
    out << "</DataArray>\n";
    scalar("zone", [&](int k) { return nodes[k].zone + 1; });
    scalar("D_kk", [&](int k) { return nodes[k].pressure_area; });
    out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";

    files.write(directory + "/contact_surface.pvd", [](std::ostream &pvd) {
      DataOutBase::write_pvd_record(pvd, {{0.0, "contact_surface.vtu"}});
    });
  }
} // namespace FetiContact
