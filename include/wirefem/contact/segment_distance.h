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
} // namespace wirefem::contact
