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
    const Vec2 chord = m.corners[1] - m.corners[0];
    m.cut_normal = (1.0 / core::norm(chord)) * core::perp(chord);
    if (core::dot(m.cut_normal, m.axis) < 0.0)
      m.cut_normal = -1.0 * m.cut_normal;
    m.cut_origin =
        m.inlet +
        (core::dot(m.corners[0] - m.inlet, m.cut_normal) / core::dot(m.axis, m.cut_normal)) * m.axis;
    return m;
  }

  InitialCurve::InitialCurve(const ChannelMouth &left, const ChannelMouth &right)
  {
    const double third = core::norm(right.inlet - left.inlet) / 3.0;
    control = {{left.inlet, left.inlet + third * left.axis, right.inlet + third * right.axis, right.inlet}};
    tabulate();
  }

  InitialCurve::InitialCurve(const ChannelMouth &channel, const double stub_length)
  {
    const Vec2 step = (stub_length / 3.0) * channel.axis;
    control = {{channel.inlet, channel.inlet + step, channel.inlet + 2.0 * step, channel.inlet + 3.0 * step}};
    tabulate();
  }

  void InitialCurve::tabulate()
  {
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

  double InitialCurve::turning() const
  {
    const int n = static_cast<int>(table.size()) - 1;
    double sum = 0.0;
    Vec2 before = tangent(0.0);
    for (int k = 1; k <= n; ++k)
      {
        const Vec2 t = tangent(double(k) / n);
        sum += std::atan2(core::cross(before, t), core::dot(before, t));
        before = t;
      }
    return sum;
  }

  double hold_beyond_mouth(const bool tangential, const double r_inlet, const double diameter,
                           const double angle)
  {
    return (tangential ? std::sqrt(2.0 * r_inlet * diameter) + diameter : 0.0) +
           diameter * std::tan(angle * M_PI / 180.0);
  }

  double free_end_length(const geometry::Cavity &cavity, const ChannelMouth &channel)
  {
    // March along the axis from past the mouth in steps of d/4 until the
    // point leaves the cavity (no chord is longer than half the
    // perimeter), then bisect.
    const double reach = 0.5 * cavity.perimeter();
    const auto inside = [&](const double t) { return cavity.contains(channel.inlet + t * channel.axis); };
    double lo = std::max(channel.corner_depth[0], channel.corner_depth[1]) + 0.5, hi = lo;
    if (!inside(lo))
      throw std::invalid_argument("the channel's axis leaves the cavity within d/2 of its mouth");
    while (inside(hi) && hi < reach)
      {
        lo = hi;
        hi += 0.25;
      }
    for (int i = 0; i < 60; ++i)
      {
        const double mid = 0.5 * (lo + hi);
        (inside(mid) ? lo : hi) = mid;
      }
    return 0.25 * (lo + hi);
  }

  InitialCurve initial_curve(const ChannelledWall &wall, const double unit)
  {
    if (wall.mouths.size() == 2)
      return InitialCurve(wall.mouths[0], wall.mouths[1]);
    const double length = free_end_length(wall.cavity, wall.mouths[0]);
    return InitialCurve(wall.mouths[0],
                        unit > 0.0 ? std::max(1.0, std::round(length / unit)) * unit : length);
  }

  InitialShape initial_shape(const unsigned int seed, const double amplitude, const double mirror_asymmetry,
                             const InitialCurve &curve, const std::size_t n_channels)
  {
    return InitialShape(seed, amplitude, (n_channels == 2 ? 1.0 : 2.0) * curve.length(), mirror_asymmetry);
  }

  ChannelledWall::ChannelledWall(geometry::Cavity cavity_in, std::vector<ChannelMouth> mouths_in)
    : cavity(std::move(cavity_in))
    , mouths(std::move(mouths_in))
  {
  }

  bool touch_corner(const Vec2 &corner, const Vec2 &p, const double half_d, double &overlap, Vec2 &towards)
  {
    const Vec2 to_corner = corner - p;
    const double dc = core::norm(to_corner);
    overlap = half_d - dc;
    if (overlap <= 0.0)
      return false;
    towards = (1.0 / dc) * to_corner;
    return true;
  }

  void ChannelledWall::describe(core::WireState &w) const
  {
    w.wall = cavity.outline(static_cast<int>(std::ceil(1.3 * cavity.perimeter())) + 64);
    w.channels.clear();
    for (const auto &m : mouths)
      w.channels.push_back({m.inlet, m.axis});
  }

  bool ChannelledWall::touch(const Vec2 &p, const double half_d, WallTouch &out) const
  {
    // Deeper than d/2, the point touches neither the wall nor a corner of a
    // mouth (the corners lie on the wall).
    if (cavity.surely_deeper(p, half_d))
      return false;
    const auto w = cavity.nearest(p);
    for (const auto &m : mouths)
      {
        const double deepest = std::max(m.corner_depth[0], m.corner_depth[1]);
        const double shallowest = std::min(m.corner_depth[0], m.corner_depth[1]);
        // In the channel behind the mouth, or nearest to the wall where the
        // mouth opens it: the wall there is the mouth's corners.
        const bool behind = w.depth < 0.0 && std::abs(m.across(p)) < m.half_width && m.along(p) < deepest;
        const double a = m.along(w.point);
        const bool in_mouth =
            std::abs(m.across(w.point)) < m.half_width && a > shallowest - 1.0 && a < deepest + 1.0;
        if (!behind && !in_mouth)
          continue;
        const Vec2 to0 = m.corners[0] - p, to1 = m.corners[1] - p;
        out.at_corner = true;
        out.corner = core::dot(to0, to0) < core::dot(to1, to1) ? m.corners[0] : m.corners[1];
        return touch_corner(out.corner, p, half_d, out.overlap, out.towards);
      }
    out.overlap = half_d - w.depth;
    if (out.overlap <= 0.0)
      return false;
    out.at_corner = false;
    out.towards = -1.0 * w.normal;
    // The outward normal of a wall of curvature kappa turns by
    // kappa / (1 - kappa depth) per length along the tangent, at depth.
    out.spread = w.curvature / (1.0 - w.curvature * w.depth);
    return true;
  }
} // namespace wirefem::injection
