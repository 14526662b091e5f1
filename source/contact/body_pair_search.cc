#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/regions.h>
#include <feticontact/contact/body_pair_search.h>
#include <feticontact/contact/mortar.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace FetiContact::ContactSearch
{
  using namespace dealii;

  namespace
  {
    /**
     * The master vertex of @p master opposite @p x along the unit vector @p outer: of the
     * vertices within @p tolerance of the line through @p x along @p outer, the nearest to @p x
     * (the lowest vertex number of equally near ones); without any, the vertex nearest to the
     * line. Returns the vertex (invalid for a surface without vertices), its distance from the
     * line and its distance from @p x.
     */
    std::tuple<unsigned int, double, double>
    opposite_master_vertex(const Point<3>     &x,
                           const Tensor<1, 3> &outer,
                           const Surface      &master,
                           const double        tolerance)
    {
      unsigned int best        = numbers::invalid_unsigned_int;
      double       best_offset = std::numeric_limits<double>::max(),
             best_distance     = std::numeric_limits<double>::max();
      for (const auto &[mv, data] : master.vertex)
        {
          const Tensor<1, 3> d        = data.x - x;
          const double       offset   = (d - (d * outer) * outer).norm();
          const double       distance = d.norm();
          const bool         on_line = offset <= tolerance, best_on_line = best_offset <= tolerance;
          if (on_line ? (!best_on_line || distance < best_distance) :
                        (!best_on_line && offset < best_offset))
            {
              best          = mv;
              best_offset   = offset;
              best_distance = distance;
            }
        }
      return {best, best_offset, best_distance};
    }

    /**
     * The gap and normal of @p node towards the master surface: χ(x) is the master vertex
     * opposite x along its outer normal @p outer (@p partner if given, else
     * opposite_master_vertex()); the meshes must match node to node.
     */
    void
    place_opposite_master(ContactNode                       &node,
                          const Tensor<1, 3>                &outer,
                          const Surface                     &slave,
                          const Surface                     &master,
                          const Body                        &body,
                          const Body                        *master_body,
                          const Parameters::ContactZone     &zone,
                          const std::string                 &where,
                          unsigned int                      &n_touching,
                          const std::optional<unsigned int> &partner = {})
    {
      // χ(x): the master vertex opposite x along the outer normal.
      unsigned int best;
      double       best_offset;
      if (partner)
        {
          best                 = *partner;
          const Tensor<1, 3> d = master.vertex.at(best).x - node.x;
          best_offset          = (d - (d * outer) * outer).norm();
        }
      else
        std::tie(best, best_offset, std::ignore) =
          opposite_master_vertex(node.x, outer, master, 1e-6 * slave.mean_edge);
      require(best != numbers::invalid_unsigned_int && best_offset <= 1e-6 * slave.mean_edge,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' has no node of the master surface of body '" + master_body->parameters.name +
                "' opposite it: the meshes of the two surfaces do not match (they must "
                "be conforming node to node).");
      const SurfaceVertex &y = master.vertex.at(best);
      node.master            = {{zone.master_body, best, 1.0, y.x, y.copies}};
      const Tensor<1, 3> d   = y.x - node.x;
      const Tensor<1, 3> master_outer =
        master.normal_sum.at(best) / master.normal_sum.at(best).norm();
      require(master_outer * outer < 0,
              where + "the master surface <" + zone.master_surface.name() + "> of body '" +
                master_body->parameters.name +
                "' faces away from the slave surface: at the node at " + point_text(node.x) +
                " of body '" + body.parameters.name +
                "' the outer normals of the two surfaces are " + point_text(outer) + " and " +
                point_text(master_outer) +
                " (they must point towards each other; is the master surface the "
                "other side of its body?).");
      const double touching = slave.touching_depth(node.vertex);
      require(d * outer >= -touching,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' lies inside body '" + master_body->parameters.name + "' (initial penetration " +
                InputParsing::number_text(-(d * outer)) + " along its outer normal, more than " +
                touching_text(slave, node.vertex) + "): the bodies overlap before any load.");
      // Less than the touching depth inside: the node touches the master vertex.
      n_touching += d * outer < 0 ? 1 : 0;
      if (d * outer >= 0 && d.norm() > touching)
        {
          node.n   = d / d.norm();
          node.gap = d.norm();
        }
      else
        {
          node.n   = outer;
          node.gap = 0;
        }
    }

    /** The surface of a zone as the mortar coupling needs it, and the vertex numbers. */
    struct MortarSurface
    {
      Mortar::Surface                    surface;
      std::vector<unsigned int>          vertex; ///< local → mesh vertex
      std::vector<const SurfaceVertex *> data;   ///< local → its position and copies
    };

    MortarSurface
    mortar_surface(const Surface &s)
    {
      MortarSurface                        m;
      std::map<unsigned int, unsigned int> local;
      for (const auto &[v, data] : s.vertex)
        {
          local[v] = m.vertex.size();
          m.vertex.push_back(v);
          m.data.push_back(&data);
          m.surface.points.push_back(data.x);
        }
      for (const auto &t : s.triangles)
        m.surface.triangles.push_back({{local[t[0]], local[t[1]], local[t[2]]}});
      Mortar::compute_normals(m.surface, s.outward);
      return m;
    }

    /**
     * The master vertex of each home vertex of the slave surface if the coupling is that of
     * matching meshes (every slave vertex fully covered, and M_kj = D_kk for one master vertex j
     * and 0 for the others, on every rank of @p comm); nothing otherwise. Collective.
     */
    std::optional<std::map<unsigned int, unsigned int>>
    matching_partners(const std::vector<Mortar::NodeCoupling> &couplings,
                      const MortarSurface                     &slave,
                      const MortarSurface                     &master,
                      const MPI_Comm                           comm)
    {
      std::map<unsigned int, unsigned int> partner;
      const auto                           match = [&]() {
        for (unsigned int k = 0; k < couplings.size(); ++k)
          {
            if (!slave.data[k]->home)
              continue;
            const auto &c = couplings[k];
            if (c.covered <= 0 || !c.dual)
              return false;
            std::optional<unsigned int> one;
            for (const auto &[j, m] : c.M)
              if (std::abs(m / c.D - 1) <= 1e-8 && !one)
                one = j;
              else if (std::abs(m / c.D) > 1e-8)
                return false;
            if (!one)
              return false;
            partner[slave.vertex[k]] = master.vertex[*one];
          }
        return true;
      };
      const bool matches = match();
      if (Utilities::MPI::min(matches ? 1u : 0u, comm) == 0)
        return {};
      return partner;
    }

    /**
     * Refuses a mortar coupling that found nothing to couple, or an overlap of the bodies deeper
     * than the search distance. If nothing was coupled, a second coupling without a distance
     * limit tells why: surfaces facing away from each other, surfaces that do not overlap at
     * all, or a nearest master triangle beyond the search distance (in front or behind).
     */
    void
    check_mortar_coupling(const ZoneSide           &side,
                          const Body               &master_body,
                          const MortarSurface      &slave,
                          const MortarSurface      &master,
                          const Mortar::Statistics &statistics,
                          const double              distance)
    {
      const std::string pair = "the surface <" + side.zone.surface.name() + "> of body '" +
                               side.body.parameters.name + "' and the master surface <" +
                               side.zone.master_surface.name() + "> of body '" +
                               master_body.parameters.name + "'";
      const std::string overlap = side.where + "body '" + side.body.parameters.name +
                                  "' penetrates body '" + master_body.parameters.name + "' by ";
      const auto refuse_overlap = [&](const Mortar::Statistics &found) {
        throw InputError(overlap + InputParsing::number_text(-found.min_distance) + " m near " +
                         point_text(found.deepest_point) +
                         " before any load, more than the search distance " +
                         InputParsing::number_text(distance) +
                         " m: the bodies overlap (move them apart, or a larger 'Search "
                         "distance').");
      };
      if (statistics.n_segments > 0)
        {
          if (statistics.min_distance < -distance)
            refuse_overlap(statistics);
          return;
        }
      std::vector<Point<3>> all = slave.surface.points;
      all.insert(all.end(), master.surface.points.begin(), master.surface.points.end());
      const BoundingBox<3> box(all);
      Mortar::Statistics   wide;
      Mortar::couple(slave.surface,
                     master.surface,
                     box.side_length(0) + box.side_length(1) + box.side_length(2),
                     wide);
      require(wide.n_segments > 0 || wide.n_facing_away == 0,
              side.where + pair +
                " face away from each other: where they overlap, their outer normals point "
                "the same way (they must point towards each other; is the master surface the "
                "other side of its body?).");
      require(wide.n_segments > 0,
              side.where + pair +
                " do not overlap: no master triangle lies opposite a slave triangle (the right "
                "surfaces?).");
      if (wide.min_distance < 0)
        refuse_overlap(wide);
      throw InputError(side.where + pair + " are too far apart: the nearest master triangle lies " +
                       InputParsing::number_text(wide.min_distance) +
                       " m in front of the slave surface, beyond the search distance " +
                       InputParsing::number_text(distance) +
                       " m (a larger 'Search distance', if the gap may close).");
    }

    /** The mortar nodes of a zone from the coupling of its surfaces. */
    void
    add_mortar_nodes(const ZoneSide                          &side,
                     const std::vector<Mortar::NodeCoupling> &couplings,
                     const MortarSurface                     &slave,
                     const MortarSurface                     &master,
                     std::vector<ContactNode>                &nodes,
                     ZoneReport                              &report)
    {
      for (unsigned int k = 0; k < couplings.size(); ++k)
        {
          auto node = side.start_node(slave.vertex[k]);
          if (!node)
            continue;
          const auto &c = couplings[k];
          if (c.covered <= 0)
            {
              ++report.n_uncovered;
              continue;
            }
          node->n   = c.normal;
          node->gap = c.weighted_gap / c.D;
          // Less than the touching depth inside the master body: the node touches it.
          if (node->gap < 0 && node->gap >= -side.slave.touching_depth(node->vertex))
            {
              node->gap = 0;
              ++report.n_touching;
            }
          node->pressure_area = c.D;
          node->mortar        = true;
          for (const auto &[j, m] : c.M)
            node->master.push_back({side.zone.master_body,
                                    master.vertex[j],
                                    m / c.D,
                                    master.data[j]->x,
                                    master.data[j]->copies});
          report.n_partly_covered += c.dual ? 0 : 1;
          report.n_overlapping += node->gap < 0 ? 1 : 0;
          side.finish_node(*node, nodes);
        }
    }

    /**
     * The sum of the side lengths of the bounding box of the slave faces and the master faces
     * @p master_own of all ranks (how far behind a slave triangle to look for an overlap, and
     * the largest distance between the surfaces). Collective.
     */
    double
    span_of_both(const ZoneSide &side, const std::vector<SurfaceFace> &master_own)
    {
      Regions::Region both = box_of_own(side.slave);
      if (const auto m = box_of(master_own))
        Regions::merge(both, *m);
      both = Regions::union_over_ranks(side.comm, both);
      return both ? both->side_length(0) + both->side_length(1) + both->side_length(2) : 0;
    }

    /**
     * The statistics of the coupling of every rank's share: the counts added, the smallest
     * distance and the point of the lowest rank where it occurs. Collective.
     */
    void
    sum_over_ranks(Mortar::Statistics &statistics, const MPI_Comm comm)
    {
      add_over_ranks(
        {&statistics.n_candidate_pairs, &statistics.n_segments, &statistics.n_facing_away}, comm);
      const double       least = Utilities::MPI::min(statistics.min_distance, comm);
      const unsigned int rank  = Utilities::MPI::this_mpi_process(comm);
      const unsigned int holder =
        Utilities::MPI::min(statistics.min_distance == least ? rank : numbers::invalid_unsigned_int,
                            comm);
      statistics.min_distance  = least;
      statistics.deepest_point = Utilities::MPI::broadcast(comm, statistics.deepest_point, holder);
    }

    /**
     * The master surface of a body-pair zone as a rank needs it: all of it, or (the search
     * shared) the master faces near this rank's slave faces.
     */
    class MasterSurface
    {
    public:
      MasterSurface(const ZoneSide &side, const Body &body, const BoundarySelector &selector)
        : side(side)
        , body(body)
        , selector(selector)
      {
        if (side.shared())
          own = own_faces(body, selector, side.parts_of_vertex(body));
        else
          surface = collect_surface(body, selector, side.parts_of_vertex(body), Share::whole);
      }

      /**
       * Adds the master faces within @p margin of the region of every rank, @p region this
       * rank's (shared search; nothing otherwise). Collective.
       */
      void
      add_faces_near(const Regions::Region &region, const double margin)
      {
        if (!side.shared())
          return;
        std::vector<SurfaceFace> added =
          faces_in_regions(body, own, Regions::of_ranks(side.comm, region), margin);
        near.insert(near.end(), added.begin(), added.end());
        near    = exchange_faces(body, std::move(near), {});
        surface = surface_of(near, 0, [](const SurfaceFace &, unsigned int) { return true; });
      }

      /** Appends the master triangles this rank holds to @p list (Surface::append_to()). */
      void
      append_own_to(std::vector<ContactTriangle> &list,
                    const unsigned int            zone,
                    const unsigned int            body_index) const
      {
        if (side.shared())
          surface_of(own, 0, [](const SurfaceFace &, unsigned int) {
            return true;
          }).append_to(list, zone, body_index);
        else
          surface.append_to(list, zone, body_index);
      }

      /** The whole master surface (gathered if the search is shared). Collective. */
      Surface
      whole() const
      {
        return side.shared() ?
                 collect_surface(body, selector, side.parts_of_vertex(body), Share::whole) :
                 surface;
      }

      const ZoneSide         &side;
      const Body             &body;
      const BoundarySelector &selector;
      /** The faces this rank holds (shared search). */
      std::vector<SurfaceFace> own;
      /** The faces near this rank's slave faces (shared search). */
      std::vector<SurfaceFace> near;
      Surface                  surface;
    };

    /**
     * The mortar coupling of a zone's surfaces, with the statistics of all ranks. A shared
     * search couples this rank's slave faces with the master faces near them (within the search
     * distance, and behind the slave triangles without a segment), which gives the home
     * vertices' couplings of the whole surfaces.
     */
    std::vector<Mortar::NodeCoupling>
    couple_surfaces(const ZoneSide     &side,
                    MasterSurface      &master,
                    const double        distance,
                    MortarSurface      &slave_m,
                    MortarSurface      &master_m,
                    Mortar::Statistics &statistics)
    {
      slave_m = mortar_surface(side.slave);
      Mortar::Share share;
      if (side.shared())
        {
          master.add_faces_near(box_of_all(side.slave), distance);
          share.counted.assign(side.slave.own.begin(), side.slave.own.end());
          share.depth = span_of_both(side, master.own);
        }
      master_m = mortar_surface(master.surface);
      auto couplings =
        Mortar::couple(slave_m.surface, master_m.surface, distance, statistics, share);
      if (side.shared())
        {
          // A master surface deep behind a slave triangle without a segment: the faces there too.
          if (Utilities::MPI::logical_or(statistics.searched_behind.has_value(), side.comm))
            {
              master.add_faces_near(statistics.searched_behind, 0);
              master_m = mortar_surface(master.surface);
              couplings =
                Mortar::couple(slave_m.surface, master_m.surface, distance, statistics, share);
            }
          sum_over_ranks(statistics, side.comm);
        }
      return couplings;
    }

    /**
     * A shared search of a zone discretized node to node: the master faces within a distance of
     * this rank's slave faces that grows (×8, from the mean edge) until every rank finds a master
     * vertex opposite each of its home vertices, or the distance spans both surfaces (then
     * place_opposite_master() tells which node has none). Collective.
     */
    void
    add_master_faces_opposite(const ZoneSide &side, MasterSurface &master)
    {
      const double span   = span_of_both(side, master.own);
      const auto   region = box_of_all(side.slave);
      for (double reach = side.slave.mean_edge;; reach *= 8)
        {
          master.add_faces_near(region, std::min(reach, span));
          // Found: a vertex opposite every home node, and every master vertex nearer to the
          // node than it in the window (its ball lies in the window), so that the nearest one
          // is that of the whole surface.
          bool missing = false;
          for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
            if (side.start_node(vertex))
              {
                const auto [best, offset, distance] =
                  opposite_master_vertex(side.slave.vertex.at(vertex).x,
                                         normal_sum / normal_sum.norm(),
                                         master.surface,
                                         1e-6 * side.slave.mean_edge);
                missing |= offset > 1e-6 * side.slave.mean_edge || distance > reach;
              }
          if (!Utilities::MPI::logical_or(missing, side.comm) || reach >= span)
            return;
        }
    }
  } // namespace

  void
  add_uncoupled_vertices(const ZoneSide                       &side,
                         const std::vector<ContactNode>       &nodes,
                         const unsigned int                    first,
                         std::vector<ContactSurfaces::Vertex> &uncoupled)
  {
    std::set<unsigned int> coupled;
    for (unsigned int k = first; k < nodes.size(); ++k)
      coupled.insert(nodes[k].vertex);
    for (const auto &[vertex, data] : side.slave.vertex)
      if (data.home && coupled.count(vertex) == 0)
        uncoupled.push_back({side.z, side.zone.body, vertex, data.x, data.copies.parts.front()});
  }

  BoundarySelector
  resolved_surface(const Body &body, const BoundarySelector &selection, const std::string &where)
  {
    BoundarySelector surface(selection);
    try
      {
        surface.resolve(body.mesh,
                        body.parameters.name,
                        body.mesh_comm(),
                        body.parameters.mesh.transform);
      }
    catch (const InputError &e)
      {
        throw InputError(where + e.what());
      }
    return surface;
  }

  void
  add_body_pair_nodes(const ZoneSide                           &side,
                      const std::vector<std::unique_ptr<Body>> &bodies,
                      std::vector<ContactNode>                 &nodes,
                      ZoneReport                               &report)
  {
    using Discretization               = Parameters::ContactZone::Discretization;
    const auto            &zone        = side.zone;
    const Body            &master_body = *bodies[zone.master_body];
    const BoundarySelector master_selector =
      resolved_surface(master_body, zone.master_surface, side.where + "Master surface: ");
    MasterSurface master(side, master_body, master_selector);

    std::optional<std::map<unsigned int, unsigned int>> partner;
    if (zone.discretization != Discretization::node_to_node)
      {
        report.search_distance = zone.search_distance.value_or(side.slave.mean_edge);
        MortarSurface      slave_m, master_m;
        Mortar::Statistics statistics;
        const auto         couplings =
          couple_surfaces(side, master, report.search_distance, slave_m, master_m, statistics);
        report.n_segments = statistics.n_segments;
        if (statistics.n_segments == 0 && side.shared())
          check_mortar_coupling(side,
                                master_body,
                                mortar_surface(collect_surface(side.body,
                                                               side.selector,
                                                               side.parts_of_vertex(side.body),
                                                               Share::whole)),
                                mortar_surface(master.whole()),
                                statistics,
                                report.search_distance);
        else
          check_mortar_coupling(
            side, master_body, slave_m, master_m, statistics, report.search_distance);
        if (zone.discretization == Discretization::automatic)
          partner = matching_partners(couplings, slave_m, master_m, side.comm);
        if (!partner)
          {
            report.discretization = "mortar";
            MPITools::collectively<InputError>(side.comm, [&]() {
              add_mortar_nodes(side, couplings, slave_m, master_m, nodes, report);
            });
            if (side.surfaces != nullptr)
              master.append_own_to(side.surfaces->master, side.z, zone.master_body);
            return;
          }
      }
    else if (side.shared())
      add_master_faces_opposite(side, master);
    if (side.surfaces != nullptr)
      master.append_own_to(side.surfaces->master, side.z, zone.master_body);
    report.discretization = "node to node";
    MPITools::collectively<InputError>(side.comm, [&]() {
      for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
        if (auto node = side.start_node(vertex))
          {
            std::optional<unsigned int> hint;
            if (partner && partner->count(vertex) > 0)
              hint = partner->at(vertex);
            place_opposite_master(*node,
                                  normal_sum / normal_sum.norm(),
                                  side.slave,
                                  master.surface,
                                  side.body,
                                  &master_body,
                                  zone,
                                  side.where,
                                  report.n_touching,
                                  hint);
            side.finish_node(*node, nodes);
          }
    });
  }
} // namespace FetiContact::ContactSearch
