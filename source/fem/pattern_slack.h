// How far K's contact pattern is from missing a pair (not installed).
#pragma once

#include <wirefem/contact/broad_phase.h>
#include <wirefem/core/vec2.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace wirefem::fem
{
  /// The candidate pairs outside K's pattern, as last measured: each with
  /// its slack, how much farther apart its chords were than the contact
  /// reach `reach`, when their nodes, [lo, lo + at.size()), were at `at`.
  /// Two chords approach each other by at most twice the largest move of
  /// their nodes, so a pair whose slack exceeds that (plus any growth of
  /// the reach) cannot touch yet; only the others need their distance.
  /// Valid for one list of candidates (the broad phase's rebuild count)
  /// and one pattern (cleared when the pattern is built).
  struct PatternSlack
  {
    struct Entry
    {
      contact::SegmentPair pair;
      double slack;
    };
    bool valid = false;
    double reach = 0.0;
    unsigned int broad_rebuilds = 0;
    int lo = 0;
    std::vector<core::Vec2> at;
    std::vector<Entry> outside; ///< sorted by slack

    /// The least slack a pair needs to be safe now without a measurement
    /// (infinite: nothing known). position(k) is node k now.
    template <typename Position>
    double needed(const double reach_now, const unsigned int rebuilds, const Position &position) const
    {
      if (!valid || rebuilds != broad_rebuilds)
        return INFINITY;
      double moved2 = 0.0;
      for (std::size_t m = 0; m < at.size(); ++m)
        moved2 = std::max(moved2, core::norm_square(position(lo + static_cast<int>(m)) - at[m]));
      // (plus a margin far above the rounding of a distance)
      return 2.0 * std::sqrt(moved2) + std::max(0.0, reach_now - reach) + 1e-12;
    }
  };
} // namespace wirefem::fem
