#include <wirefem/scene/cavity_setup.h>

#include <cmath>
#include <stdexcept>

namespace wirefem::scene
{
  bool general_wall(const CavityParameters &c, const InjectionParameters &in)
  {
    const auto &p = in.channel_positions;
    const bool default_positions = p.size() == 2 && p[0] == 0.5 && p[1] == 0.0;
    return c.shape != CavityShape::circle || in.channel_angle != 0.0 || !default_positions;
  }

  geometry::Cavity cavity_wall(const CavityParameters &c)
  {
    const double r = c.radius;
    switch (c.shape)
      {
      case CavityShape::circle:
        return geometry::Cavity::circle(r);
      case CavityShape::ellipse:
        {
          const double q = std::sqrt(c.aspect_ratio);
          return geometry::Cavity::ellipse(r * q, r / q);
        }
      case CavityShape::polygon:
        break;
      }
    if (c.vertices.size() % 2 != 0)
      throw std::invalid_argument("needs x, y pairs: an even count of numbers, not " +
                                  std::to_string(c.vertices.size()));
    std::vector<core::Vec2> v;
    double twice_area = 0.0;
    for (std::size_t i = 0; i + 1 < c.vertices.size(); i += 2)
      v.push_back({c.vertices[i], c.vertices[i + 1]});
    for (std::size_t i = 0; i < v.size(); ++i)
      twice_area += core::cross(v[i], v[(i + 1) % v.size()]);
    const double polygon_area = 0.5 * std::abs(twice_area);
    if (!(polygon_area > 0.0))
      throw std::invalid_argument("the vertices enclose no area");
    // Scale the sharp polygon to the target area, round its corners, and
    // correct the scale for the area the arcs cut off: with sharp area
    // s^2 A0, rounding at a fixed radius removes a fixed area, so one
    // correction is exact. Then move the centroid to the origin.
    const double target = M_PI * r * r;
    auto scaled = [&](const double s) {
      std::vector<core::Vec2> w;
      for (const auto &p : v)
        w.push_back(s * p);
      return w;
    };
    // (The first build is at twice the sharp scale, where a corner radius
    // that fits the final polygon fits too.)
    const double s0 = 2.0 * std::sqrt(target / polygon_area);
    const double cut = s0 * s0 * polygon_area - geometry::Cavity::polygon(scaled(s0), c.corner_radius).area();
    const double s = std::sqrt((target + cut) / polygon_area);
    auto w = scaled(s);
    const core::Vec2 centre = geometry::Cavity::polygon(w, c.corner_radius).centroid();
    for (auto &p : w)
      p = p - centre;
    return geometry::Cavity::polygon(std::move(w), c.corner_radius);
  }

  double wall_start(const geometry::Cavity &wall)
  {
    // The first wall point, counter-clockwise, whose angle about the
    // centroid passes from below the +x axis to above it: a scan of n
    // points, then bisection.
    const double length = wall.perimeter();
    const auto angle = [&](const double s) {
      const core::Vec2 q = wall.at(s).point - wall.centroid();
      return std::atan2(q.y, q.x);
    };
    const int n = 4096;
    for (int k = 0; k < n; ++k)
      {
        double lo = length * k / n, hi = length * (k + 1) / n;
        const double a0 = angle(lo), a1 = angle(hi);
        if (!(a0 < 0.0 && a1 >= 0.0 && a1 - a0 < M_PI))
          continue;
        for (int i = 0; i < 100 && hi - lo > 1e-15 * length; ++i)
          {
            const double mid = 0.5 * (lo + hi);
            (angle(mid) < 0.0 ? lo : hi) = mid;
          }
        return hi;
      }
    return 0.0;
  }

  std::vector<injection::ChannelMouth> channel_mouths(const geometry::Cavity &wall,
                                                      const InjectionParameters &in)
  {
    const double angle = in.channel_angle * M_PI / 180.0;
    const double start =
        wall.shape() == geometry::Cavity::Shape::polygon ? wall_start(wall) / wall.perimeter() : 0.0;
    std::vector<injection::ChannelMouth> mouths;
    for (const double f : in.channel_positions)
      mouths.push_back(injection::place_channel(wall, std::fmod(start + f, 1.0), angle, 1.0));
    return mouths;
  }

  std::shared_ptr<const injection::ChannelledWall> channelled_wall(const CavityParameters &cavity,
                                                                   const InjectionParameters &injection)
  {
    auto wall = cavity_wall(cavity);
    auto mouths = channel_mouths(wall, injection);
    return std::make_shared<const injection::ChannelledWall>(std::move(wall), std::move(mouths));
  }
} // namespace wirefem::scene
