// Exact closest points between two segments of the centreline.
#pragma once

#include <wirefem/geometry/vec2.h>

namespace wirefem::contact
{
  /// Closest points p = a0 + s (a1 - a0) and q = b0 + t (b1 - b0) of two
  /// segments, s, t in [0, 1]; distance = |p - q| (units of the inputs).
  /// For parallel overlapping segments one of the (equally close) pairs is
  /// returned, chosen deterministically.
  struct ClosestPoints
  {
    double s = 0.0;
    double t = 0.0;
    double distance = 0.0;
    geometry::Vec2 p;
    geometry::Vec2 q;
  };

  ClosestPoints closest_points(const geometry::Vec2 &a0, const geometry::Vec2 &a1, const geometry::Vec2 &b0,
                               const geometry::Vec2 &b1);

  /// The gap between the two segments' bounding boxes, the larger of the
  /// gaps along x and y (negative where the boxes overlap): a lower bound of
  /// the segments' distance at the cost of a few comparisons, so a caller
  /// can skip closest_points for a pair that cannot be in contact.
  inline double box_gap(const geometry::Vec2 &a0, const geometry::Vec2 &a1, const geometry::Vec2 &b0,
                        const geometry::Vec2 &b1)
  {
    const auto gap = [](const double p0, const double p1, const double q0, const double q1) {
      const double plo = p0 < p1 ? p0 : p1, phi = p0 < p1 ? p1 : p0;
      const double qlo = q0 < q1 ? q0 : q1, qhi = q0 < q1 ? q1 : q0;
      const double g1 = qlo - phi, g2 = plo - qhi;
      return g1 > g2 ? g1 : g2;
    };
    const double gx = gap(a0.x, a1.x, b0.x, b1.x), gy = gap(a0.y, a1.y, b0.y, b1.y);
    return gx > gy ? gx : gy;
  }
} // namespace wirefem::contact
