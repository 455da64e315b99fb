// The sticking springs of the rod FEM's self contacts under the discrete
// model's friction law (FEM/Self friction law = spring): one per (node,
// segment) pair that touched at the last accepted step, kept sorted by
// pair so that lookups, commits and the checkpoint go in one order.
#pragma once

#include <wirefem/contact/friction_law.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace wirefem::fem
{
  /// One spring, as the checkpoint stores it (no padding).
  struct PairSpring
  {
    std::int64_t node = 0, segment = 0;
    double elongation = 0.0;
    std::int64_t sliding = 0;

    bool operator<(const PairSpring &o) const { return node != o.node ? node < o.node : segment < o.segment; }
  };
  static_assert(sizeof(PairSpring) == 4 * 8, "PairSpring has padding");

  class PairSprings
  {
  public:
    /// The committed spring of node against segment. A node that slid
    /// across a node of the other wire onto the neighbouring segment keeps
    /// the spring it had there, as in the discrete model; without one, a
    /// relaxed spring.
    contact::FrictionHistory find(const int node, const int segment) const
    {
      for (const int s : {segment, segment - 1, segment + 1})
        {
          const PairSpring key{node, s, 0.0, 0};
          const auto it = std::lower_bound(springs.begin(), springs.end(), key);
          if (it != springs.end() && it->node == node && it->segment == s)
            return {it->elongation, it->sliding != 0};
        }
      return {};
    }
    /// The springs of an accepted step, in any order: they replace the
    /// committed ones (a pair that no longer touches lets its spring go).
    void commit(std::vector<PairSpring> trial)
    {
      std::sort(trial.begin(), trial.end());
      springs = std::move(trial);
    }
    const std::vector<PairSpring> &all() const { return springs; }

  private:
    std::vector<PairSpring> springs;
  };
} // namespace wirefem::fem
