#include <deal.II/base/exceptions.h>

#include <feticontact/feti/load_balance.h>

#include <algorithm>
#include <numeric>

namespace FetiContact::LoadBalance
{
  std::vector<unsigned int>
  proportional_ranges(const std::vector<double> &weight_start, const std::vector<double> &speed)
  {
    AssertThrow(!weight_start.empty() && !speed.empty(),
                dealii::ExcMessage("LoadBalance: no weights or no ranks."));
    const unsigned int n = weight_start.size() - 1, n_ranks = speed.size();
    const double       total_speed = std::accumulate(speed.begin(), speed.end(), 0.);
    AssertThrow(total_speed > 0, dealii::ExcMessage("LoadBalance: the speeds are not positive."));
    const double              total = weight_start.back() - weight_start.front();
    std::vector<unsigned int> first(n_ranks + 1, n);
    first[0]                = 0;
    double speed_before     = 0;
    for (unsigned int p = 1; p < n_ranks; ++p)
      {
        speed_before += speed[p - 1];
        const double target = weight_start.front() + total * speed_before / total_speed;
        // Range p begins at the first subdomain whose preceding weight reaches the target (the
        // rule of BlockPartition::balanced, which gives the starting ranges).
        const unsigned int i =
          std::lower_bound(weight_start.begin(), weight_start.end() - 1, target) -
          weight_start.begin();
        first[p] = std::max(i, first[p - 1]);
      }
    return first;
  }

  Proposal
  propose(const std::vector<double>       &weight_start,
          const std::vector<unsigned int> &first,
          const std::vector<double>       &local_time,
          const std::vector<double>       &build_time_per_weight,
          const double                     fixed_cost)
  {
    const unsigned int n_ranks = local_time.size();
    AssertThrow(first.size() == n_ranks + 1 && build_time_per_weight.size() == n_ranks,
                dealii::ExcMessage("LoadBalance: one range, time and build time per rank."));
    Proposal proposal;
    proposal.first = first;
    const auto weight_of = [&](const std::vector<unsigned int> &ranges, const unsigned int r) {
      return weight_start[ranges[r + 1]] - weight_start[ranges[r]];
    };

    // Speeds; a rank without weight or time gets the mean speed of the others.
    std::vector<double> speed(n_ranks, 0.);
    double              sum = 0;
    unsigned int        n_measured = 0;
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        proposal.time_now = std::max(proposal.time_now, local_time[r]);
        if (weight_of(first, r) > 0 && local_time[r] > 0)
          {
            speed[r] = weight_of(first, r) / local_time[r];
            sum += speed[r];
            ++n_measured;
          }
      }
    if (n_ranks < 2 || n_measured == 0)
      {
        proposal.time_balanced = proposal.time_now;
        return proposal;
      }
    for (unsigned int r = 0; r < n_ranks; ++r)
      if (speed[r] == 0)
        speed[r] = sum / n_measured;

    const std::vector<unsigned int> balanced = proportional_ranges(weight_start, speed);
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        proposal.time_balanced = std::max(proposal.time_balanced, weight_of(balanced, r) / speed[r]);
        // The arriving subdomains: the new range without the old one.
        const unsigned int begin = balanced[r], end = balanced[r + 1];
        const unsigned int keep_begin = std::max(begin, first[r]);
        const unsigned int keep_end   = std::max(keep_begin, std::min(end, first[r + 1]));
        const double       arriving =
          (weight_start[end] - weight_start[begin]) - (weight_start[keep_end] - weight_start[keep_begin]);
        proposal.cost = std::max(proposal.cost, arriving * build_time_per_weight[r]);
      }
    proposal.cost += fixed_cost;
    if (balanced != first && proposal.time_now - proposal.time_balanced >= proposal.cost)
      {
        proposal.first = balanced;
        proposal.move  = true;
      }
    return proposal;
  }
} // namespace FetiContact::LoadBalance
