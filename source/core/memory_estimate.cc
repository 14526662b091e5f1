#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/core/memory_estimate.h>
#include <feticontact/scene/lattice_parts.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <unistd.h>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    // The model's coefficients, least squares fit to the peaks measured by
    // benchmarks/memory_model.py (doc/performance.md, "Memory").
    constexpr double baseline_mib        = 182.0;   ///< M₀
    constexpr double mib_per_cell        = 4.59e-4; ///< a
    constexpr double mib_per_factor_unit = 2.05e-4; ///< b_f
    /**
     * a_m: a cell of a whole mesh alone (Triangulation::memory_consumption(): 136.2 MiB for the
     * 196,608 cells of the brick at k = 32, doc/data/communication_k32.md).
     */
    constexpr double mib_per_mesh_cell = 136.2 / 196608;
    /** The largest relative error of the model on the measured peaks, rounded up. */
    constexpr double model_error = 0.1;

    constexpr double unlimited = std::numeric_limits<double>::infinity();

    /**
     * The counts after the $Nodes and $Elements headers of a Gmsh file (MSH 2 or 4), each at
     * most what the file's size can hold (a node line has at least 8 characters, an element
     * line 10): a header that promises more belongs to a truncated file, which the mesh reader
     * names as such.
     */
    std::pair<double, double>
    gmsh_counts(const std::string &file)
    {
      std::error_code error;
      const double    size = static_cast<double>(std::filesystem::file_size(file, error));
      if (error)
        return {0, 0}; // the mesh reader names the cause
      std::ifstream in(file);
      std::string   line;
      double        nodes = 0, elements = 0;
      const auto    count = [&]() {
        std::getline(in, line);
        std::istringstream words(line);
        double             first = 0, second = 0;
        words >> first;
        // MSH 4: "numEntityBlocks numNodes minTag maxTag"; MSH 2: "numNodes".
        return (words >> second) ? second : first;
      };
      while (std::getline(in, line))
        {
          const std::string word = InputParsing::trim(line);
          if (word == "$Nodes")
            nodes = count();
          else if (word == "$Elements")
            {
              elements = count();
              break;
            }
        }
      return {std::min(nodes, size / 8), std::min(elements, size / 10)};
    }

    /** Tetrahedra and vertices of a body's mesh, before it is built. */
    std::pair<double, double>
    mesh_size(const Parameters::Mesh &mesh)
    {
      if (mesh.type == Parameters::Mesh::Type::gmsh)
        {
          const auto [nodes, elements] = gmsh_counts(mesh.file);
          return {elements, nodes};
        }
      const auto  &s     = mesh.subdivisions;
      const double cubes = double(s[0]) * s[1] * s[2];
      return {mesh.tetrahedra_per_cube * cubes, (s[0] + 1.0) * (s[1] + 1.0) * (s[2] + 1.0)};
    }

    /**
     * The number after @p key (or "key:") at the start of a line of @p file, as in /proc/meminfo
     * and a cgroup's memory.stat; NaN if there is none.
     */
    double
    keyed_number(const std::string &file, const std::string &key)
    {
      std::ifstream in(file);
      std::string   line;
      while (std::getline(in, line))
        {
          std::istringstream words(line);
          std::string        name;
          double             value = 0;
          if (words >> name >> value && (name == key || name == key + ":"))
            return value;
        }
      return std::numeric_limits<double>::quiet_NaN();
    }

    /** A number of bytes in a cgroup file, in MiB (infinite if absent or "max"). */
    double
    cgroup_mib(const std::string &file)
    {
      std::ifstream in(file);
      double        bytes = 0;
      if (!(in >> bytes))
        return unlimited;
      return bytes / (1024.0 * 1024.0);
    }

    /**
     * The folders of the memory cgroups this process is in, innermost first, each followed by
     * its ancestors up to the root of its hierarchy (a limit of any of them applies): cgroup v2
     * (`0::/path` in /proc/self/cgroup, under /sys/fs/cgroup or /sys/fs/cgroup/unified) and v1
     * (the `memory` controller, under /sys/fs/cgroup/memory), with the names of their limit,
     * usage, reclaimable page cache and page cache entries.
     */
    struct Cgroup
    {
      std::string folder, limit, usage, inactive_key, cache_key;
    };

    std::vector<Cgroup>
    memory_cgroups()
    {
      std::vector<Cgroup> found;
      const auto          add_with_ancestors =
        [&](const std::string &mount, std::string path, const Cgroup &names) {
          if (!std::filesystem::is_directory(mount))
            return;
          while (true)
            {
              Cgroup c = names;
              c.folder = mount + (path == "/" ? "" : path);
              if (std::filesystem::exists(c.folder + "/" + c.limit))
                found.push_back(c);
              if (path.empty() || path == "/")
                break;
              path = std::filesystem::path(path).parent_path().string();
            }
        };
      const Cgroup v2{"", "memory.max", "memory.current", "inactive_file", "file"};
      const Cgroup v1{
        "", "memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file", "total_cache"};
      std::ifstream in("/proc/self/cgroup");
      std::string   line;
      while (std::getline(in, line))
        {
          // hierarchy-ID:controller-list:path
          const auto first = line.find(':'), second = line.find(':', first + 1);
          if (first == std::string::npos || second == std::string::npos)
            continue;
          const std::string controllers = line.substr(first + 1, second - first - 1);
          const std::string path        = line.substr(second + 1);
          if (line.compare(0, first, "0") == 0 && controllers.empty())
            for (const std::string mount : {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"})
              add_with_ancestors(mount, path, v2);
          else
            for (const auto &c : InputParsing::split(controllers, ','))
              if (c == "memory")
                add_with_ancestors("/sys/fs/cgroup/memory", path, v1);
        }
      // Inside a container the process's cgroup is the mount's root.
      add_with_ancestors("/sys/fs/cgroup", "/", v2);
      add_with_ancestors("/sys/fs/cgroup/memory", "/", v1);
      return found;
    }

    /**
     * What this machine and the memory cgroups of this process can give the ranks of a node,
     * their own resident memory (@p anon_mib anonymous, @p file_mib mapped files: the program's
     * libraries) included: for the machine, MemAvailable plus both; for a cgroup, its limit less
     * its usage plus its reclaimable page cache, plus what the ranks hold that the cgroup counts
     * (their anonymous memory, and their mapped files only as far as its page cache has them:
     * libraries read before the process joined the cgroup are charged elsewhere).
     */
    struct Available
    {
      double mib = unlimited;
      /** What limits it, for messages. */
      std::string source = "MemAvailable of /proc/meminfo";
    };

    Available
    available_on_machine(const double anon_mib, const double file_mib)
    {
      const double mem_available = keyed_number("/proc/meminfo", "MemAvailable"); // kB
      Available    available;
      if (!std::isnan(mem_available))
        available.mib = mem_available / 1024 + anon_mib + file_mib;
      for (const Cgroup &c : memory_cgroups())
        {
          const double max = cgroup_mib(c.folder + "/" + c.limit);
          if (!std::isfinite(max) || max >= 1e12) // "max", or v1's "no limit" (2⁶³ bytes)
            continue;
          const auto stat_mib = [&](const std::string &key) {
            const double bytes = keyed_number(c.folder + "/memory.stat", key);
            return std::isnan(bytes) ? 0.0 : bytes / (1024.0 * 1024.0);
          };
          // A cgroup's usage counts the page cache, whose inactive part the kernel reclaims.
          const double free = max - cgroup_mib(c.folder + "/" + c.usage) +
                              stat_mib(c.inactive_key) + anon_mib +
                              std::min(file_mib, stat_mib(c.cache_key));
          if (free < available.mib)
            available = {free,
                         "the limit " + InputParsing::number_text(std::round(max)) +
                           " MiB of the memory cgroup <" + c.folder + ">, less its usage"};
        }
      return available;
    }

    /** The resident memory of this process now, in MiB: anonymous, and mapped files. */
    std::array<double, 2>
    resident_mib()
    {
      const double anon = keyed_number("/proc/self/status", "RssAnon"); // kB
      const double file = keyed_number("/proc/self/status", "RssFile");
      return {{std::isnan(anon) ? 0.0 : anon / 1024, std::isnan(file) ? 0.0 : file / 1024}};
    }

    /** M for the bodies scaled by @p s (subdivisions of boxes, cells of Gmsh meshes). */
    struct Model
    {
      std::vector<double> cells, vertices, parts;
      std::vector<bool>   box;
      bool                monolithic = false;
      /** Whether the cells are distributed, and which bodies rank 0 creates whole then. */
      bool              distributed = false;
      std::vector<bool> whole_on_root;
      unsigned int      n_ranks       = 1;
      unsigned int      ranks_on_node = 1; ///< the least over the machines of the run

      double
      cells_at(const unsigned int b, const double s) const
      {
        return cells[b] * (box[b] ? s * s * s : s);
      }

      double
      factor_units(const double s) const
      {
        double units = 0, whole = 0;
        for (unsigned int b = 0; b < cells.size(); ++b)
          {
            const double v = vertices[b] * (box[b] ? s * s * s : s);
            // A part's vertices with the copies on its interfaces: the body as a cube of
            // ∛V vertices a side, cut into P cubes.
            const double v_part = std::pow((std::cbrt(v) - 1) / std::cbrt(parts[b]) + 1, 3);
            units += parts[b] * std::pow(3 * v_part, 4.0 / 3.0);
            whole += std::pow(3 * v, 4.0 / 3.0);
          }
        // The monolithic solve (rank 0 alone) shared among the ranks of its machine, whose
        // memory they share.
        return units * share() + (monolithic ? whole / ranks_on_node : 0);
      }

      /** The largest rank's share of the parts. */
      double
      share() const
      {
        double n_parts = 0;
        for (const double p : parts)
          n_parts += p;
        return std::ceil(n_parts / n_ranks) / n_parts;
      }

      double
      peak_mib(const double s) const
      {
        // Distributed cells: the rank's share of them, and on rank 0 the whole meshes that it
        // creates and cuts.
        double c = 0, whole = 0;
        for (unsigned int b = 0; b < cells.size(); ++b)
          {
            c += cells_at(b, s);
            if (distributed && whole_on_root[b])
              whole += cells_at(b, s);
          }
        if (distributed)
          c *= share();
        return baseline_mib + mib_per_cell * c + mib_per_mesh_cell * whole +
               mib_per_factor_unit * factor_units(s);
      }
    };

    Model
    model_of(const Parameters::Scene &scene, const unsigned int n_ranks)
    {
      Model model;
      model.n_ranks     = n_ranks;
      model.distributed = n_ranks > 1;
      model.monolithic  = scene.verification.compare_with_monolithic && scene.contact.zones.empty();
      for (const auto &body : scene.bodies)
        {
          const auto [c, v] = mesh_size(body.mesh);
          model.cells.push_back(c);
          model.vertices.push_back(v);
          // More parts than cells is refused when the body is built, with its own message.
          model.parts.push_back(std::clamp<double>(body.decomposition.n_parts_for(body.mesh, v),
                                                   1.0,
                                                   std::max(1.0, c)));
          model.box.push_back(body.mesh.type == Parameters::Mesh::Type::box);
          model.whole_on_root.push_back(!LatticeParts::of(body).has_value());
        }
      return model;
    }

    std::string
    gib_text(const double mib)
    {
      std::ostringstream text;
      text.precision(mib < 10 * 1024 ? 2 : 3);
      text << mib / 1024 << " GiB";
      return text.str();
    }
  } // namespace

  MemoryEstimate
  MemoryEstimate::of(const Parameters::Scene &scene, const MPI_Comm comm)
  {
    MemoryEstimate estimate;
    MPI_Comm       node;
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    estimate.ranks_on_node = Utilities::MPI::n_mpi_processes(node);
    const auto   own       = resident_mib();
    const double anon      = Utilities::MPI::sum(own[0], node);
    const double file      = Utilities::MPI::sum(own[1], node);
    MPI_Comm_free(&node);

    Model model           = model_of(scene, Utilities::MPI::n_mpi_processes(comm));
    model.ranks_on_node   = Utilities::MPI::min(estimate.ranks_on_node, comm);
    estimate.peak_mib     = model.peak_mib(1);
    estimate.factor_units = model.factor_units(1);
    for (unsigned int b = 0; b < model.cells.size(); ++b)
      estimate.cells += model.cells[b];

    // Per rank, the least over the nodes: the memory free on the node plus what its ranks
    // already hold (the program and its libraries, part of M₀).
    const Available available = available_on_machine(anon, file);
    estimate.available_mib    = Utilities::MPI::min(available.mib / estimate.ranks_on_node, comm);
    estimate.available_source = available.source;

    if (!estimate.fits())
      {
        // The scale that fits, by bisection on its logarithm: scales down to 1e-12 of the mesh.
        double low = -12, high = 0;
        if (model.peak_mib(std::pow(10.0, low)) > estimate.available_mib)
          estimate.fitting_scale = 0;
        else
          {
            for (unsigned int it = 0; it < 60; ++it)
              {
                const double s = 0.5 * (low + high);
                (model.peak_mib(std::pow(10.0, s)) <= estimate.available_mib ? low : high) = s;
              }
            estimate.fitting_scale = std::pow(10.0, low);
          }
      }
    return estimate;
  }

  bool
  MemoryEstimate::fits() const
  {
    return !((1 - model_error) * peak_mib > available_mib);
  }

  bool
  MemoryEstimate::tight() const
  {
    return peak_mib > available_mib;
  }

  void
  MemoryEstimate::check(const Parameters::Scene &scene) const
  {
    if (fits())
      return;
    std::ostringstream text;
    text << "the estimated peak memory of this run, " << gib_text(peak_mib) << " per rank ("
         << ranks_on_node << " rank(s) on this machine; "
         << InputParsing::number_text(std::round(cells))
         << " tetrahedra), exceeds by more than the model's error of "
         << InputParsing::number_text(100 * model_error) << " % the " << gib_text(available_mib)
         << " per rank that this process can use (" << available_source << ")";
    const bool boxes = std::all_of(scene.bodies.begin(), scene.bodies.end(), [](const auto &b) {
      return b.mesh.type == Parameters::Mesh::Type::box;
    });
    if (fitting_scale == 0)
      text << "; not even a mesh of one cell per subdomain fits";
    else if (boxes)
      {
        text << "; with the same decomposition about this fits:";
        for (unsigned int b = 0; b < scene.bodies.size(); ++b)
          {
            const auto &s = scene.bodies[b].mesh.subdivisions;
            text << (b ? "," : "") << " Body " << b + 1 << "/Mesh/Subdivisions = ";
            for (unsigned int d = 0; d < 3; ++d)
              text << (d ? ", " : "")
                   << InputParsing::number_text(std::max(1.0, std::floor(s[d] * fitting_scale)));
          }
      }
    else
      text << "; with the same decomposition about "
           << InputParsing::number_text(100 * fitting_scale) << " % of the cells fit";
    text << " (the model: doc/performance.md, \"Memory\")";
    throw InputError(text.str());
  }
} // namespace FetiContact
