// Exact closest points between two segments of the centreline.
#pragma once

#include <wirefem/core/vec2.h>

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
    core::Vec2 p;
    core::Vec2 q;
  };

  ClosestPoints closest_points(const core::Vec2 &a0, const core::Vec2 &a1, const core::Vec2 &b0,
                               const core::Vec2 &b1);

  /// The gap between the two segments' bounding boxes, the larger of the
  /// gaps along x and y (negative where the boxes overlap): a lower bound of
  /// the segments' distance at the cost of a few comparisons, so a caller
  /// can skip closest_points for a pair that cannot be in contact.
  inline double box_gap(const core::Vec2 &a0, const core::Vec2 &a1, const core::Vec2 &b0,
                        const core::Vec2 &b1)
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

  /// The point q = a + t (b - a) of a segment closest to p, t in [0, 1], and
  /// |p - q|^2; at either end q is the end node itself, so two segments that
  /// meet at a node report exactly the same distance from it.
  struct PointOnSegment
  {
    double t = 0.0;
    core::Vec2 q;
    double distance2 = 0.0;
  };

  inline PointOnSegment closest_on_segment(const core::Vec2 &p, const core::Vec2 &a, const core::Vec2 &b)
  {
    const core::Vec2 e = b - a;
    const double ee = dot(e, e);
    double t = ee > 0.0 ? dot(p - a, e) / ee : 0.0;
    core::Vec2 q;
    if (t <= 0.0)
      t = 0.0, q = a;
    else if (t >= 1.0)
      t = 1.0, q = b;
    else
      q = a + t * e;
    return {t, q, norm_square(p - q)};
  }

  /// Node-to-segment contact of both models: whether segment `seg` (nodes
  /// seg, seg + 1 of a polyline x(k)), at squared distance `distance2` from
  /// the point p, is the nearest to p of its stretch of wire, i.e. closer
  /// than its neighbours seg - 1 and seg + 1 where `allowed` lets p touch
  /// them (ties go to the lower segment). Only that segment presses p, so
  /// the contact energy is that of p's distance to the stretch, continuous
  /// as p glides past its nodes; counting every segment within reach counts
  /// p twice on one side of each node it passes.
  template <typename Position, typename Allowed>
  bool nearest_of_stretch(const core::Vec2 &p, const int seg, const double distance2, const Position &x,
                          const Allowed &allowed)
  {
    if (allowed(seg - 1) && !(distance2 < closest_on_segment(p, x(seg - 1), x(seg)).distance2))
      return false;
    return !(allowed(seg + 1) && closest_on_segment(p, x(seg + 1), x(seg + 2)).distance2 < distance2);
  }
} // namespace wirefem::contact
