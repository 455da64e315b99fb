// Observables of a wire state: packing density, loops, morphology.
#pragma once

#include <wirefem/core/wire_state.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace wirefem::analysis
{
  /// phi = d L / (pi r^2).
  double packing_density(double injected_length, double radius, double diameter = 1.0);

  /// Number of loops (docs/analysis.md, Loops): faces of the planar map of the
  /// centreline and its self-contacts (each a chord between its two contact
  /// points) whose boundary is one contiguous stretch of wire closed by
  /// exactly one contact. A stretch zipped shut along its length (a run of
  /// contacts) is one loop: only its innermost chord closes an empty face.
  /// A face that also touches another contact (a loop with a smaller loop
  /// hanging into it, the gap between two touching strands) is not one.
  int count_loops(const core::WireState &wire);

  /// count_loops on the planar graph of the wire and its chords, traced
  /// face by face: segments that cross properly are split at their
  /// crossing point (rounded); -1 when segments overlap, touch other than
  /// at a common end, or the rounding leaves them so (exact predicates).
  /// count_loops falls back to the arrangement then.
  int count_loops_planar(const core::WireState &wire);

  /// count_loops through CGAL's arrangement with exact constructions alone
  /// (crossings split edges): the fall-back, and the tests' reference.
  int count_loops_arrangement(const core::WireState &wire);

  /// The self-contacts of a wire from its geometry alone: pieces of the
  /// centreline closer than d whose rest arc lengths are more than
  /// `exclusion_length` apart, one contact per pair of pieces (a contact at
  /// a shared point is reported once). For shapes that come without contacts.
  std::vector<core::SelfContact> find_self_contacts(const core::WireState &wire,
                                                    double exclusion_length = 3.0);

  struct Morphology
  {
    std::string phase; ///< spiral | classic | plastic
    double curvature_ratio =
        0.0; ///< A/B: squared curvature in the inner disc over the outer ring (equal areas)
    /// A/B splits into where the wire is and how curved it is there:
    /// A/B = f/(1 - f) * (A/L_in)/(B/L_out), with f = L_in/(L_in + L_out) the
    /// share of the wire's length inside the inner disc (0.5 for wire spread
    /// evenly over the cavity) and the second factor the ratio of squared
    /// curvature per length inside to that outside.
    double inner_wire_fraction = 0.0;
    double curvature_density_ratio = 0.0; ///< (A/L_in)/(B/L_out)
    double symmetry = 0.0; ///< 1 = mirror-symmetric about the axis perpendicular to the channels, 0 = none
    double winding_left =
        0.0; ///< polar angle swept around the centre from the left inlet to mid-wire (turns)
    double winding_right = 0.0; ///< same from the right inlet (turns)
    /// Share of the wire's length in stretches that wind at least one full
    /// turn round the centre without turning back (polar angle monotonic).
    double coiled_fraction = 0.0;
  };

  /// Spiral when at least `spiral_fraction` of the wire is coiled
  /// (Morphology::coiled_fraction); otherwise classic if A/B < 0.5 (the
  /// paper's criterion), else plastic.
  Morphology classify(const core::WireState &wire, double spiral_fraction = 0.5);

  /// The numbers of a Morphology under their summary.json / `wirefem analyze`
  /// keys, so every writer lists the same keys.
  inline std::array<std::pair<const char *, double>, 7> morphology_numbers(const Morphology &m)
  {
    return {{{"symmetry", m.symmetry},
             {"curvature_ratio", m.curvature_ratio},
             {"inner_wire_fraction", m.inner_wire_fraction},
             {"curvature_density_ratio", m.curvature_density_ratio},
             {"winding_left", m.winding_left},
             {"winding_right", m.winding_right},
             {"coiled_fraction", m.coiled_fraction}}};
  }
} // namespace wirefem::analysis
