#include <wirefem/contact/segment_distance.h>

#include <cmath>

namespace wirefem::contact
{
  using core::Vec2;

  namespace
  {
    /// Parameter in [0, 1] of the point of segment o + u d closest to p.
    /// Comparing before dividing means the quotient is only formed when
    /// 0 < num < len2, so a zero or tiny len2 never produces inf or NaN.
    inline double clamped_projection(const Vec2 &p, const Vec2 &o, const Vec2 &d, const double len2)
    {
      const double num = core::dot(p - o, d);
      if (num <= 0.0)
        return 0.0;
      if (num >= len2)
        return 1.0;
      return num / len2;
    }

    inline bool opposite_signs(const double a, const double b)
    {
      return (a > 0.0 && b < 0.0) || (a < 0.0 && b > 0.0);
    }

    /// Whether the segments cross properly; then result holds the crossing.
    bool proper_crossing(const Vec2 &a0, const Vec2 &a1, const Vec2 &b0, const Vec2 &b1,
                         ClosestPoints &result)
    {
      const Vec2 da = a1 - a0;
      const Vec2 db = b1 - b0;
      // Proper crossing. The parameters come from the orientation values
      // themselves: with strictly opposite signs |o1 - o2| = |o1| + |o2| > 0,
      // also after rounding, so the quotients are finite and lie in [0, 1]
      // without a separate parallelism tolerance.
      const double o1 = core::cross(da, b0 - a0);
      const double o2 = core::cross(da, b1 - a0);
      if (opposite_signs(o1, o2))
        {
          const double o3 = core::cross(db, a0 - b0);
          const double o4 = core::cross(db, a1 - b0);
          if (opposite_signs(o3, o4))
            {
              result.s = o3 / (o3 - o4);
              result.t = o1 / (o1 - o2);
              result.p = a0 + result.s * da;
              result.q = b0 + result.t * db;
              result.distance = 0.0;
              return true;
            }
        }
      return false;
    }
  } // namespace

  ClosestPoints closest_points(const Vec2 &a0, const Vec2 &a1, const Vec2 &b0, const Vec2 &b1)
  {
    const Vec2 da = a1 - a0;
    const Vec2 db = b1 - b0;

    ClosestPoints result;

    if (proper_crossing(a0, a1, b0, b1, result))
      return result;

    // In 2D two segments that do not cross properly have a closest pair with an
    // end point of one of them (touching, collinear and parallel cases
    // included), so the four end point to segment distances are exhaustive.
    // They are tried in a fixed order and only a strictly smaller distance
    // replaces the current one, which makes ties (parallel overlaps)
    // deterministic.
    const double la = core::norm_square(da);
    const double lb = core::norm_square(db);

    // a0 against segment b.
    double t = clamped_projection(a0, b0, db, lb);
    double best = core::norm_square(a0 - (b0 + t * db));
    double best_s = 0.0;
    double best_t = t;

    // a1 against segment b.
    t = clamped_projection(a1, b0, db, lb);
    double candidate = core::norm_square(a1 - (b0 + t * db));
    if (candidate < best)
      {
        best = candidate;
        best_s = 1.0;
        best_t = t;
      }

    // b0 against segment a.
    double s = clamped_projection(b0, a0, da, la);
    candidate = core::norm_square((a0 + s * da) - b0);
    if (candidate < best)
      {
        best = candidate;
        best_s = s;
        best_t = 0.0;
      }

    // b1 against segment a.
    s = clamped_projection(b1, a0, da, la);
    candidate = core::norm_square((a0 + s * da) - b1);
    if (candidate < best)
      {
        best = candidate;
        best_s = s;
        best_t = 1.0;
      }

    result.s = best_s;
    result.t = best_t;
    // Endpoints are taken verbatim rather than recomputed from s = 0 or 1, so
    // p and q are exactly the input points where the parameter is clamped.
    result.p = (best_s == 0.0) ? a0 : (best_s == 1.0) ? a1 : a0 + best_s * da;
    result.q = (best_t == 0.0) ? b0 : (best_t == 1.0) ? b1 : b0 + best_t * db;
    result.distance = std::sqrt(core::norm_square(result.p - result.q));
    return result;
  }
} // namespace wirefem::contact
