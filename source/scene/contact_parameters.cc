#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/rigid_obstacle.h>
#include <feticontact/scene/contact_parameters.h>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  ContactZone::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type",
                      "rigid plane",
                      Patterns::Selection("rigid plane|rigid sphere|rigid cylinder|body"),
                      "What the surface may touch: a 'rigid plane' (given by a point and a "
                      "normal), a 'rigid sphere' (a centre and a radius), a 'rigid cylinder' (a "
                      "point of its axis, the axis and a radius), or another 'body' (its 'Master "
                      "surface').");
    prm.declare_entry("Body",
                      "1",
                      Patterns::Integer(1),
                      "The body whose surface this is (1, 2, …).");
    prm.declare_entry("Surface",
                      "z = zmin",
                      Patterns::Anything(),
                      "The candidate contact surface Γ_c of the body: a boundary id or a plane "
                      "such as 'z = zmin'. Vertices with a prescribed displacement component are "
                      "not contact nodes.");
    prm.declare_entry("Friction coefficient",
                      "0",
                      Patterns::Anything(),
                      "Coulomb's coefficient of friction μ ≥ 0 (dimensionless); 0 is "
                      "frictionless contact.");
    prm.declare_entry("Plane point",
                      "0, 0, 0",
                      Patterns::Anything(),
                      "Rigid plane: a point of the plane (m).");
    prm.declare_entry("Plane normal",
                      "0, 0, 1",
                      Patterns::Anything(),
                      "Rigid plane: its normal pointing out of the obstacle, towards the body "
                      "(normalized on input).");
    prm.declare_entry("Centre",
                      "0, 0, 0",
                      Patterns::Anything(),
                      "Rigid sphere: its centre; rigid cylinder: a point of its axis (m).");
    prm.declare_entry("Axis",
                      "0, 0, 1",
                      Patterns::Anything(),
                      "Rigid cylinder: the direction of its axis (normalized on input).");
    prm.declare_entry("Radius",
                      "1",
                      Patterns::Double(0),
                      "Rigid sphere and rigid cylinder: the radius (m), > 0.");
    prm.declare_entry("Master body", "2", Patterns::Integer(1), "Body pair: the other body.");
    prm.declare_entry("Master surface",
                      "z = zmax",
                      Patterns::Anything(),
                      "Body pair: the surface of the other body facing this one.");
    prm.declare_entry("Discretization",
                      "automatic",
                      Patterns::Selection("automatic|node to node|mortar"),
                      "Body pair: how the rows couple the two surfaces. 'node to node': each "
                      "node against the master vertex opposite it (the meshes must match there); "
                      "'mortar': dual mortar rows, for meshes that do not match; 'automatic': "
                      "node to node where the surfaces match node for node, mortar otherwise.");
    prm.declare_entry("Search distance",
                      "auto",
                      Patterns::Anything(),
                      "Body pair, mortar: how far in front of a slave triangle a master triangle "
                      "is still coupled with it, and how deep the master surface may lie behind "
                      "the slave surface before any load (an overlap the solve removes) (m); "
                      "'auto': the mean edge length of the slave surface. Rigid sphere and "
                      "cylinder: nodes farther from the obstacle are not contact nodes, nodes up "
                      "to this deep inside it before any load are pushed out by the solve; "
                      "'auto': every node is a contact node and none may start inside.");
  }

  void
  ContactZone::parse_parameters(ParameterHandler &prm, const unsigned int n_bodies)
  {
    const std::string type_text = prm.get("Type");
    type                        = type_text == "rigid plane"    ? Type::rigid_plane :
                                  type_text == "rigid sphere"   ? Type::rigid_sphere :
                                  type_text == "rigid cylinder" ? Type::rigid_cylinder :
                                                                  Type::body;
    body                        = prm.get_integer("Body") - 1;
    require(body < n_bodies,
            "Body = " + prm.get("Body") + " but the scene has " + std::to_string(n_bodies) +
              " bodies.");
    surface = BoundarySelector::parse(prm.get("Surface"), "Surface");
    friction_coefficient =
      InputParsing::parse_double(prm.get("Friction coefficient"), "Friction coefficient");
    require(friction_coefficient >= 0,
            "Friction coefficient must not be negative; got " + prm.get("Friction coefficient") +
              ".");
    if (type == Type::rigid_plane)
      {
        plane_point  = InputParsing::parse_point(prm.get("Plane point"), "Plane point");
        plane_normal = InputParsing::parse_vector(prm.get("Plane normal"), "Plane normal");
        require(plane_normal.norm() > 0, "Plane normal must not be the zero vector.");
        plane_normal /= plane_normal.norm();
      }
    else if (type != Type::body)
      {
        centre = InputParsing::parse_point(prm.get("Centre"), "Centre");
        radius = prm.get_double("Radius");
        require(radius > 0, "Radius must be positive; got " + prm.get("Radius") + ".");
        if (type == Type::rigid_cylinder)
          {
            axis = InputParsing::parse_vector(prm.get("Axis"), "Axis");
            require(axis.norm() > 0, "Axis must not be the zero vector.");
            axis /= axis.norm();
          }
      }
    else
      {
        master_body = prm.get_integer("Master body") - 1;
        require(master_body < n_bodies,
                "Master body = " + prm.get("Master body") + " but the scene has " +
                  std::to_string(n_bodies) + " bodies.");
        require(master_body != body, "Master body must differ from Body.");
        master_surface = BoundarySelector::parse(prm.get("Master surface"), "Master surface");
        const std::string method = prm.get("Discretization");
        discretization           = method == "mortar"       ? Discretization::mortar :
                                   method == "node to node" ? Discretization::node_to_node :
                                                              Discretization::automatic;
      }
    const std::string distance = InputParsing::trim(prm.get("Search distance"));
    if (distance != "auto")
      {
        search_distance = InputParsing::parse_double(distance, "Search distance");
        require(*search_distance >= 0,
                "Search distance must not be negative (or 'auto'); got " + distance + ".");
      }
    obstacle = make_rigid_obstacle(*this);
  }

  void
  Contact::declare_parameters(ParameterHandler &prm, const unsigned int n_zones)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("Number of zones",
                      "0",
                      Patterns::Integer(0, 256),
                      "The number of contact zones, each described in 'subsection Zone N'.");
    for (unsigned int z = 1; z <= n_zones; ++z)
      {
        prm.enter_subsection("Zone " + std::to_string(z));
        ContactZone::declare_parameters(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();
  }

  void
  Contact::parse_parameters(ParameterHandler &prm, const unsigned int n_bodies)
  {
    prm.enter_subsection("Contact");
    zones.resize(prm.get_integer("Number of zones"));
    for (unsigned int z = 0; z < zones.size(); ++z)
      {
        const std::string section = "Zone " + std::to_string(z + 1);
        prm.enter_subsection(section);
        try
          {
            zones[z].parse_parameters(prm, n_bodies);
          }
        catch (const InputError &e)
          {
            throw InputError("subsection Contact/" + section + ": " + e.what());
          }
        prm.leave_subsection();
      }
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters

namespace FetiContact
{
  bool
  in_contact(const Parameters::Contact &contact, const unsigned int b)
  {
    for (const auto &zone : contact.zones)
      if (zone.body == b ||
          (zone.type == Parameters::ContactZone::Type::body && zone.master_body == b))
        return true;
    return false;
  }
} // namespace FetiContact
