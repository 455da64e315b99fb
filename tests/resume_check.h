// What the models' save/load tests share: a run continued straight on
// beside the same run saved part way and continued from its checkpoint.
#pragma once

#include <wirefem/core/model.h>

#include <sstream>

namespace wirefem::checks
{
  /// Runs `first` to injected length `middle`, loads its saved state into
  /// `resumed`, then runs `straight` and `resumed` to `end`. The three are
  /// built from one scene; the test compares `straight` and `resumed`.
  inline void run_straight_and_resumed(core::Model &straight, core::Model &first, core::Model &resumed,
                                       const double middle, const double end)
  {
    while (first.injected_length() < middle)
      first.step();
    std::stringstream buffer;
    first.save(buffer);
    resumed.load(buffer);
    while (straight.injected_length() < end)
      straight.step();
    while (resumed.injected_length() < end)
      resumed.step();
  }
} // namespace wirefem::checks
