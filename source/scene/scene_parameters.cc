#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/scene_parameters.h>

#include <algorithm>
#include <fstream>
#include <sstream>

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
  }

  void
  Scene::parse_parameters(ParameterHandler &prm, const std::string &base_directory)
  {
    const unsigned int n_bodies = prm.get_integer("Number of bodies");
    bodies.resize(n_bodies);
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        const std::string section = "Body " + std::to_string(b + 1);
        prm.enter_subsection(section);
        try
          {
            bodies[b].parse_parameters(prm, base_directory);
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
    verification.parse_parameters(prm);
  }

  namespace
  {
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

  void
  Scene::read_parameter_file(ParameterHandler               &prm,
                             const std::string              &filename,
                             const std::vector<std::string> &overrides)
  {
    std::ifstream in(filename);
    require(static_cast<bool>(in), "Cannot open the parameter file <" + filename + ">.");
    std::stringstream buffer;
    buffer << in.rdbuf() << '\n';
    const std::string file_text = buffer.str();
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
    const std::string text       = buffer.str();
    const auto        file_lines = std::count(file_text.begin(), file_text.end(), '\n');
    const auto        describe   = [&](const std::exception &e) {
      std::string       msg   = user_part_of(e);
      const std::string label = "<input string>";
      for (auto pos = msg.find(label); pos != std::string::npos; pos = msg.find(label))
        msg.replace(pos, label.size(), "<" + filename + ">");
      const auto line = msg.find("Line <");
      if (line != std::string::npos && std::stol(msg.substr(line + 6)) > file_lines)
        msg += " (this line comes from a --set option)";
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
        throw InputError(describe(e));
      }
  }
} // namespace FetiContact::Parameters
