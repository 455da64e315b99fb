// Observables of a wire state: packing density, loops, morphology.
#pragma once

#include <wirefem/analysis/wire_state.h>

#include <string>

namespace wirefem::analysis
{
  /// phi = d L / (pi r^2).
  double packing_density(double injected_length, double radius, double diameter = 1.0);

  /// Number of loops. Provisional rule: each contiguous stretch of
  /// self-contact (pairs whose contact points lie within 2 d of each other
  /// along both wires) closes one loop.
  int count_loops(const WireState &wire);

  struct Morphology
  {
    std::string phase; ///< spiral | classic | plastic
    double curvature_ratio =
        0.0;               ///< A/B: squared curvature in the inner disc over the outer ring (equal areas)
    double symmetry = 0.0; ///< 1 = mirror-symmetric about the axis perpendicular to the channels, 0 = none
    double winding_left =
        0.0; ///< polar angle swept around the centre from the left inlet to mid-wire (turns)
    double winding_right = 0.0; ///< same from the right inlet (turns)
  };

  /// Spiral when both halves of the wire wind at least `spiral_turns` around
  /// the centre in the same sense; otherwise classic if A/B < 0.5 (the
  /// paper's criterion), else plastic.
  Morphology classify(const WireState &wire, double spiral_turns = 0.75);
} // namespace wirefem::analysis
