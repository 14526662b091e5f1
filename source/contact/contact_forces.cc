#include <feticontact/base/exact_sum.h>
#include <feticontact/contact/contact_forces.h>

#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  ContactForces
  ContactForces::of(const std::vector<ContactNode>       &nodes,
                    const std::vector<ContactNodeResult> &results,
                    const unsigned int                    n_bodies,
                    const unsigned int                    n_zones,
                    const MPI_Comm                        comm)
  {
    // Per body: force (3) and magnitudes (1); per zone: on slave (3) and on master (3).
    std::vector<ExactSum> sum(4 * n_bodies + 6 * n_zones);
    const auto            body = [&](const unsigned int b) { return sum.begin() + 4 * b; };
    const auto zone = [&](const unsigned int z) { return sum.begin() + 4 * n_bodies + 6 * z; };
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const auto        &node = nodes[k];
        const Tensor<1, 3> force =
          -(results[k].lambda_N * node.n + results[k].lambda_T[0] * node.t1 +
            results[k].lambda_T[1] * node.t2);
        for (unsigned int c = 0; c < 3; ++c)
          {
            body(node.body)[c].add(force[c]);
            body(node.body)[3].add(std::abs(force[c]));
            zone(node.zone)[c].add(force[c]);
            if (!node.on_body())
              zone(node.zone)[3 + c].add(-force[c]);
          }
        for (const auto &m : node.master)
          for (unsigned int c = 0; c < 3; ++c)
            {
              zone(node.zone)[3 + c].add(-m.weight * force[c]);
              if (!m.copies.prescribed[c])
                {
                  body(m.body)[c].add(-m.weight * force[c]);
                  body(m.body)[3].add(std::abs(m.weight * force[c]));
                }
            }
      }
    ExactSum::sum_over_ranks(sum, comm);
    ContactForces forces;
    forces.on_body.resize(n_bodies);
    forces.of_zone.resize(n_zones);
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        for (unsigned int c = 0; c < 3; ++c)
          forces.on_body[b].force[c] = body(b)[c].value();
        forces.on_body[b].magnitudes = body(b)[3].value();
      }
    for (unsigned int z = 0; z < n_zones; ++z)
      for (unsigned int c = 0; c < 3; ++c)
        {
          forces.of_zone[z].on_slave[c]  = zone(z)[c].value();
          forces.of_zone[z].on_master[c] = zone(z)[3 + c].value();
        }
    return forces;
  }
} // namespace FetiContact
