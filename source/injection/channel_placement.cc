#include <wirefem/injection/channel_placement.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wirefem::injection
{
  using core::Vec2;

  namespace
  {
    /// The distance t past the inlet along the axis where the line
    /// start + t axis crosses the wall nearest to t = 0: the first change of
    /// sign of the wall's signed distance on a scan outwards from 0 in both
    /// directions (steps of reach / 400, up to reach), then bisection.
    double crossing(const geometry::Cavity &cavity, const Vec2 &start, const Vec2 &axis, const double reach)
    {
      const auto depth = [&](const double t) { return cavity.nearest(start + t * axis).depth; };
      const double step = reach / 400.0;
      const double d0 = depth(0.0);
      if (d0 == 0.0)
        return 0.0;
      double lo = 0.0, hi = 0.0;
      bool found = false;
      double previous[2] = {0.0, 0.0}; // last t scanned forwards and backwards
      for (int k = 1; k <= 400 && !found; ++k)
        for (const int direction : {1, -1})
          {
            const double t = direction * k * step;
            if ((depth(t) > 0.0) != (d0 > 0.0))
              {
                lo = previous[direction > 0 ? 0 : 1];
                hi = t;
                found = true;
                break;
              }
            previous[direction > 0 ? 0 : 1] = t;
          }
      if (!found)
        throw std::invalid_argument(
            "the channel's side wall does not cross the cavity's wall near its inlet");
      // depth(lo) has d0's sign, depth(hi) the other.
      for (int i = 0; i < 200 && std::abs(hi - lo) > 1e-14 * reach; ++i)
        {
          const double mid = 0.5 * (lo + hi);
          ((depth(mid) > 0.0) == (d0 > 0.0) ? lo : hi) = mid;
        }
      return 0.5 * (lo + hi);
    }
  } // namespace

  ChannelMouth place_channel(const geometry::Cavity &cavity, const double position, const double angle,
                             const double width)
  {
    if (!(angle >= 0.0 && angle < 0.5 * M_PI))
      throw std::invalid_argument("the channel's angle must be in [0, 90) degrees");
    const auto w = cavity.at(position * cavity.perimeter());
    const double c = std::cos(angle), s = std::sin(angle);
    ChannelMouth m;
    m.inlet = w.point;
    // The inward normal turned clockwise by the angle.
    m.axis = {c * w.normal.x + s * w.normal.y, -s * w.normal.x + c * w.normal.y};
    m.half_width = 0.5 * width;
    const double reach = 4.0 * width / c;
    for (int side = 0; side < 2; ++side)
      {
        const Vec2 start = m.inlet + ((side == 0 ? 1.0 : -1.0) * m.half_width) * core::perp(m.axis);
        m.corner_depth[side] = crossing(cavity, start, m.axis, reach);
        m.corners[side] = start + m.corner_depth[side] * m.axis;
      }
    return m;
  }

  InitialCurve::InitialCurve(const ChannelMouth &left, const ChannelMouth &right)
  {
    const double third = core::norm(right.inlet - left.inlet) / 3.0;
    control = {{left.inlet, left.inlet + third * left.axis, right.inlet + third * right.axis, right.inlet}};
    // Arc length by Simpson's rule on each of n intervals of the parameter.
    const int n = 2048;
    table.assign(n + 1, 0.0);
    for (int k = 0; k < n; ++k)
      {
        const double u0 = double(k) / n, u1 = double(k + 1) / n;
        table[k + 1] = table[k] + (u1 - u0) / 6.0 *
                                      (core::norm(tangent(u0)) + 4.0 * core::norm(tangent(0.5 * (u0 + u1))) +
                                       core::norm(tangent(u1)));
      }
  }

  Vec2 InitialCurve::point(const double u) const
  {
    const double v = 1.0 - u;
    return (v * v * v) * control[0] + (3.0 * v * v * u) * control[1] + (3.0 * v * u * u) * control[2] +
           (u * u * u) * control[3];
  }

  Vec2 InitialCurve::tangent(const double u) const
  {
    const double v = 1.0 - u;
    return (3.0 * v * v) * (control[1] - control[0]) + (6.0 * v * u) * (control[2] - control[1]) +
           (3.0 * u * u) * (control[3] - control[2]);
  }

  InitialCurve::Point InitialCurve::at(const double s_in) const
  {
    const double s = std::clamp(s_in, 0.0, length());
    const int n = static_cast<int>(table.size()) - 1;
    const int k = std::clamp(
        static_cast<int>(std::upper_bound(table.begin(), table.end(), s) - table.begin()) - 1, 0, n - 1);
    // Within the interval: linear in the parameter, then Newton steps on
    // the arc length, whose derivative is the speed.
    double u = (k + (s - table[k]) / std::max(table[k + 1] - table[k], 1e-300)) / n;
    for (int i = 0; i < 3; ++i)
      {
        const double u0 = double(k) / n;
        const double du = u - u0;
        const double length_to_u =
            table[k] + du / 6.0 *
                           (core::norm(tangent(u0)) + 4.0 * core::norm(tangent(0.5 * (u0 + u))) +
                            core::norm(tangent(u)));
        u -= (length_to_u - s) / core::norm(tangent(u));
      }
    const Vec2 t = tangent(u);
    return {point(u), core::perp((1.0 / core::norm(t)) * t)};
  }
} // namespace wirefem::injection
