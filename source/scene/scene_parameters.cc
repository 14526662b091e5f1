#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/rigid_obstacle.h>
#include <feticontact/scene/parameter_file.h>
#include <feticontact/scene/scene_parameters.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  Scene::declare_parameters(ParameterHandler  &prm,
                            const unsigned int n_bodies,
                            const unsigned int n_zones)
  {
    prm.declare_entry("Number of bodies",
                      "1",
                      Patterns::Integer(1, 64),
                      "The number of elastic bodies; each is described in 'subsection Body N'.");
    for (unsigned int b = 1; b <= n_bodies; ++b)
      {
        prm.enter_subsection("Body " + std::to_string(b));
        Body::declare_parameters(prm);
        prm.leave_subsection();
      }
    Contact::declare_parameters(prm, n_zones);
    ContactSolver::declare_parameters(prm);
    Feti::declare_parameters(prm);
    Output::declare_parameters(prm);
    Verification::declare_parameters(prm);
    RefinementStudy::declare_parameters(prm);
  }

  void
  Scene::parse_parameters(ParameterHandler &prm, const EntryOrigins &origins)
  {
    const unsigned int n_bodies = prm.get_integer("Number of bodies");
    bodies.resize(n_bodies);
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        const std::string section = "Body " + std::to_string(b + 1);
        prm.enter_subsection(section);
        try
          {
            bodies[b].parse_parameters(prm, origins.in(section));
          }
        catch (const InputError &e)
          {
            throw InputError("subsection " + section + ": " + e.what());
          }
        prm.leave_subsection();
        if (bodies[b].name.empty())
          bodies[b].name = "body " + std::to_string(b + 1);
      }
    contact.parse_parameters(prm, n_bodies);
    contact_solver.parse_parameters(prm);
    feti.parse_parameters(prm);
    output.parse_parameters(prm);
    verification.parse_parameters(prm, origins.in("Verification"));
    refinement_study.parse_parameters(prm);
    if (verification.hertz.enabled)
      {
        // The obstacle's radius (0: flat), or nothing where Hertz's point contact does not apply.
        const auto obstacle_radius = [](const ContactZone &zone) {
          return zone.rigid() ? zone.obstacle->hertz_radius() : std::optional<double>(0.);
        };
        require(!contact.zones.empty() && obstacle_radius(contact.zones[0]),
                "Verification/Hertz: contact zone 1 must be a rigid plane, a rigid sphere or a "
                "body pair.");
        const auto &zone = contact.zones[0];
        const auto &body = bodies[zone.body];
        require(verification.hertz.sphere_radius > 0 || body.mesh.spherical_bottom_radius > 0 ||
                  *obstacle_radius(zone) > 0 ||
                  (!zone.rigid() && bodies[zone.master_body].mesh.spherical_bottom_radius > 0),
                "Verification/Hertz: no sphere radius (set Verification/Hertz/Sphere radius, or "
                "give body '" +
                  body.name + "' a Spherical bottom radius).");
      }
    if (output.write_fclib)
      {
        require(!contact.zones.empty(),
                "Output/Write FCLIB problem: the scene has no contact zones (FCLIB's problems "
                "have contacts).");
        require(contact_solver.friction_law == ContactSolver::FrictionLaw::coulomb,
                "Output/Write FCLIB problem: FCLIB's problems have Coulomb friction; this scene "
                "sets Contact solver/Friction law = tresca.");
      }
    if (!refinement_study.subdivision_factors.empty())
      for (const auto &body : bodies)
        require(body.mesh.type == Mesh::Type::box,
                "Refinement study: body '" + body.name +
                  "' reads its mesh from a file; a refinement study multiplies the Subdivisions "
                  "of generated box meshes.");
  }

  void
  RefinementStudy::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Refinement study");
    prm.declare_entry(
      "Subdivision factors",
      "",
      Patterns::Anything(),
      "Empty: solve the scene once. Else a comma-separated list of factors, "
      "e.g. '1, 1.5, 2, 3': the scene is solved once per factor with the "
      "Subdivisions of every (box) body multiplied by it and rounded, into "
      "Output/Directory/cycle-N, and Output/Directory/convergence_table.txt "
      "(and .org, refinement_study.json) tabulates unknowns, h_min, iterations, "
      "time and, with Verification/Hertz, the errors of a and p0 with their "
      "rates against the factor (deal.II's ConvergenceTable; each cell's size scales as "
      "1/factor).");
    prm.leave_subsection();
  }

  void
  RefinementStudy::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Refinement study");
    const std::string text = InputParsing::trim(prm.get("Subdivision factors"));
    prm.leave_subsection();
    subdivision_factors.clear();
    if (text.empty())
      return;
    for (const auto &item : InputParsing::split(text, ','))
      {
        const double f = InputParsing::parse_double(item, "Refinement study/Subdivision factors");
        require(f > 0 && std::isfinite(f),
                "Refinement study/Subdivision factors must be positive; got '" +
                  InputParsing::trim(item) + "'.");
        require(subdivision_factors.empty() || f > subdivision_factors.back(),
                "Refinement study/Subdivision factors must increase; got '" + text + "'.");
        subdivision_factors.push_back(f);
      }
  }

  namespace
  {
    /**
     * A hint for deal.II's message about an undeclared entry @p message ("No entry with name
     * <X> was declared in the current subsection") when X is an entry of one of the
     * subsections of `subsection Contact solver` (Expert, MPGP, SMALBE) given elsewhere, or one
     * that was removed because it lost on every measured scene; empty otherwise.
     */
    std::string
    hint_for_unknown_entry(const std::string &message)
    {
      const std::string marker = "No entry with name <";
      const auto        start  = message.find(marker);
      if (start == std::string::npos)
        return "";
      const auto end = message.find('>', start + marker.size());
      // deal.II may break its message across lines: the entry's words joined by single spaces.
      std::string entry;
      for (const auto &word :
           InputParsing::split(message.substr(start + marker.size(), end - start - marker.size()),
                               ' '))
        for (const auto &part : InputParsing::split(word, '\n'))
          if (!InputParsing::trim(part).empty())
            entry += (entry.empty() ? "" : " ") + InputParsing::trim(part);
      if (entry == "Penalty norm")
        return " (MPGP's penalty is always a multiple of ‖PFP‖ and the paper's algorithms' of ‖F‖: "
               "the entry was removed)";
      if (entry == "Maximum SMALBE iterations" || entry == "Maximum inner iterations")
        return std::string(" (the limit of ") +
               (entry == "Maximum SMALBE iterations" ? "SMALBE's outer iterations" :
                                                       "MPGP's steps per inner solve") +
               " is 'Maximum iterations' in 'subsection Contact solver', 'subsection " +
               (entry == "Maximum SMALBE iterations" ? "SMALBE" : "MPGP") + "')";
      if (entry == "Preconditioner")
        return " (preconditioning MPGP in face was removed from the contact solver; 'subsection "
               "FETI' has the preconditioner of problems without contact)";
      // Where the contact solver declares an entry of that name: its subsections, walked in
      // the short listing of its parameters.
      ParameterHandler solver;
      ContactSolver::declare_parameters(solver);
      std::ostringstream listing;
      solver.print_parameters(listing, ParameterHandler::ShortPRM);
      std::istringstream       lines(listing.str());
      std::vector<std::string> path;
      for (std::string line; std::getline(lines, line);)
        {
          const std::string text = InputParsing::trim(line);
          if (text.compare(0, 11, "subsection ") == 0)
            path.push_back(InputParsing::trim(text.substr(11)));
          else if (text == "end" && !path.empty())
            path.pop_back();
          else if (text.compare(0, 4, "set ") == 0 && path.size() > 1)
            {
              const std::string head = "set " + entry;
              if (text.compare(0, head.size(), head) != 0 ||
                  InputParsing::trim(text.substr(head.size())).compare(0, 1, "=") != 0)
                continue;
              std::string where;
              for (const auto &p : path)
                where += (where.empty() ? "'subsection " : ", 'subsection ") + p + "'";
              return " (" + entry + " is an entry of " + where + ")";
            }
        }
      return "";
    }

    /**
     * Throws InputError unless @p text (of @p filename and the --set options) opens a
     * `subsection Body N` for every body that `Number of bodies` announces and a `subsection
     * Contact / subsection Zone N` for every zone that `Contact/Number of zones` announces: a
     * body or zone is never made of defaults.
     */
    void
    require_announced_subsections(const std::string &text,
                                  const std::string &filename,
                                  const unsigned int n_bodies,
                                  const unsigned int n_zones)
    {
      const auto written = ParameterFileText::subsections(text);
      const auto missing =
        [&](const std::string &prefix, const std::string &name, const unsigned int count) {
          std::vector<std::string> absent;
          for (unsigned int i = 1; i <= count; ++i)
            if (written.count(prefix + name + " " + std::to_string(i)) == 0)
              absent.push_back("'" + name + " " + std::to_string(i) + "'");
          std::string list;
          for (unsigned int k = 0; k < absent.size(); ++k)
            list += (k == 0 ? "" : k + 1 == absent.size() ? " and " : ", ") + absent[k];
          return std::make_pair(absent.size(), list);
        };
      const auto [bodies_missing, bodies] = missing("", "Body", n_bodies);
      require(bodies_missing == 0,
              "Parameter file <" + filename + ">: 'Number of bodies = " + std::to_string(n_bodies) +
                "' announces " + std::to_string(n_bodies) + (n_bodies == 1 ? " body" : " bodies") +
                ", but the file has no subsection " + bodies +
                " (every body is described in its own subsection; none is made of defaults).");
      const auto [zones_missing, zones] = missing("Contact/", "Zone", n_zones);
      require(zones_missing == 0,
              "Parameter file <" + filename +
                ">: 'Contact/Number of zones = " + std::to_string(n_zones) + "' announces " +
                std::to_string(n_zones) + (n_zones == 1 ? " contact zone" : " contact zones") +
                ", but 'subsection Contact' has no subsection " + zones +
                " (every zone is described in its own subsection; none is made of defaults).");
    }

    /** The --set options as parameter-file text, to be appended to the file. */
    std::string
    overrides_text(const std::vector<std::string> &overrides)
    {
      std::ostringstream buffer;
      for (const auto &o : overrides)
        {
          const auto eq = o.find('=');
          require(eq != std::string::npos && eq > 0,
                  "--set <" + o + ">: expected 'Subsection/.../Entry=value'.");
          auto path = InputParsing::split(o.substr(0, eq), '/');
          require(!path.empty(), "--set <" + o + ">: no entry named.");
          const std::string entry = path.back();
          path.pop_back();
          for (const auto &p : path)
            buffer << "subsection " << p << '\n';
          buffer << "set " << entry << " = " << o.substr(eq + 1) << '\n';
          for (unsigned int k = 0; k < path.size(); ++k)
            buffer << "end\n";
        }
      return buffer.str();
    }

    /** deal.II's messages carry file and line of the library; keep the part for the user. */
    std::string
    user_part_of(const std::exception &e)
    {
      const std::string text = e.what();
      const std::string key  = "Additional information:";
      const auto        pos  = text.find(key);
      std::string       msg  = pos == std::string::npos ? text : text.substr(pos + key.size());
      const auto        end  = msg.find("Stacktrace:");
      if (end != std::string::npos)
        msg = msg.substr(0, end);
      std::string collapsed;
      bool        space = false;
      for (const char c : msg)
        {
          const bool ws = (c == ' ' || c == '\n' || c == '\t' || c == '-');
          if (ws && c != '-')
            {
              space = true;
              continue;
            }
          if (space && !collapsed.empty())
            collapsed += ' ';
          space = false;
          collapsed += c;
        }
      return InputParsing::trim(collapsed);
    }
  } // namespace

  EntryOrigins
  Scene::read_parameter_file(ParameterHandler               &prm,
                             const std::string              &filename,
                             const std::vector<std::string> &overrides,
                             std::vector<std::string>       *warnings)
  {
    const ParameterFileText file = ParameterFileText::read(filename);
    if (warnings != nullptr)
      warnings->insert(warnings->end(), file.warnings.begin(), file.warnings.end());
    std::stringstream buffer;
    buffer << file.text << '\n';
    buffer << overrides_text(overrides);
    const std::string text     = buffer.str();
    const auto        describe = [&](const std::exception &e) {
      std::string msg = user_part_of(e);
      // deal.II counts the lines of the expanded text: name the file and line they came from.
      const auto line = msg.find("Line <");
      if (line != std::string::npos)
        {
          const auto         close  = msg.find('>', line);
          const unsigned int number = std::stoul(msg.substr(line + 6));
          const std::string  label  = "of file <input string>";
          if (number >= 1 && number <= file.origin.size())
            {
              const auto &[origin_file, origin_line] = file.origin[number - 1];
              msg.replace(line, close - line + 1, "Line <" + std::to_string(origin_line) + ">");
              const auto pos = msg.find(label);
              if (pos != std::string::npos)
                msg.replace(pos, label.size(), "of file <" + origin_file + ">");
            }
          else
            msg += " (this line comes from a --set option)";
        }
      const std::string label = "<input string>";
      for (auto pos = msg.find(label); pos != std::string::npos; pos = msg.find(label))
        msg.replace(pos, label.size(), "<" + filename + ">");
      return "Parameter file <" + filename + ">: " + msg;
    };

    // First pass: the number of bodies, everything else skipped.
    unsigned int n_bodies = 1, n_zones = 0;
    {
      ParameterHandler first;
      first.declare_entry("Number of bodies", "1", Patterns::Integer(1, 64), "");
      first.enter_subsection("Contact");
      first.declare_entry("Number of zones", "0", Patterns::Integer(0, 256), "");
      first.leave_subsection();
      try
        {
          first.parse_input_from_string(text, "", true);
        }
      catch (const std::exception &e)
        {
          throw InputError(describe(e));
        }
      n_bodies = first.get_integer("Number of bodies");
      first.enter_subsection("Contact");
      n_zones = first.get_integer("Number of zones");
      first.leave_subsection();
    }

    declare_parameters(prm, n_bodies, n_zones);
    try
      {
        prm.parse_input_from_string(text, "", false);
      }
    catch (const std::exception &e)
      {
        throw InputError(describe(e) + hint_for_unknown_entry(e.what()));
      }
    require_announced_subsections(text, filename, n_bodies, n_zones);
    return EntryOrigins(file, text);
  }

  std::string
  Scene::output_directory(const std::string &filename, const std::vector<std::string> &overrides)
  {
    std::string text;
    try
      {
        text = ParameterFileText::read(filename).text + "\n" + overrides_text(overrides);
      }
    catch (const InputError &)
      {
        // A file that fails its checks (encoding, include cycle) still names its directory.
        std::ifstream in(filename, std::ios::binary);
        if (ParameterFileText::is_unrepeatable(filename))
          text = ParameterFileText::kept_text(filename);
        else if (std::filesystem::is_regular_file(filename) && in)
          {
            std::stringstream raw;
            raw << in.rdbuf();
            text = raw.str();
          }
        else
          return "";
        text += "\n" + overrides_text(overrides);
      }
    Output defaults;
    return ParameterFileText::last_value(text, "Output", "Directory", defaults.directory);
  }
} // namespace FetiContact::Parameters
