#include <wirefem/analysis/observables.h>
#include <wirefem/contact/segment_distance.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace wirefem::analysis
{
  using core::Vec2;

  double packing_density(const double injected_length, const double radius, const double diameter)
  {
    return diameter * injected_length / (M_PI * radius * radius);
  }

  namespace
  {
    // The polar angle turned from a to b about the origin (radians); 0
    // when either is at the origin.
    double polar_turn(const Vec2 a, const Vec2 b)
    {
      if (norm_square(a) < 1e-12 || norm_square(b) < 1e-12)
        return 0.0;
      return std::atan2(cross(a, b), dot(a, b));
    }

    // Polar angle swept (turns) along points[from] -> points[to].
    double winding(const std::vector<Vec2> &p, const int from, const int to)
    {
      double sweep = 0.0;
      const int step = to > from ? 1 : -1;
      for (int k = from; k != to; k += step)
        sweep += polar_turn(p[k], p[k + step]);
      return sweep / (2.0 * M_PI);
    }

    /// The share of the wire's length in stretches that wind at least one
    /// full turn round the origin without turning back: the polar angle
    /// changes monotonically along each stretch, and a stretch ends where
    /// it starts to change the other way (at a hairpin or a loop's far
    /// side). A spiral, folded or not, is coiled nearly from end to end; a
    /// packing of loops has no such stretch, though a large loop round the
    /// centre can leave a half's net winding above a turn.
    double coiled_fraction(const std::vector<Vec2> &p)
    {
      double coiled = 0.0, total = 0.0, sweep = 0.0, length = 0.0;
      int sense = 0;
      const auto end_stretch = [&] {
        if (std::abs(sweep) >= 2.0 * M_PI)
          coiled += length;
        sweep = 0.0;
        length = 0.0;
      };
      for (std::size_t k = 0; k + 1 < p.size(); ++k)
        {
          const double turn = polar_turn(p[k], p[k + 1]), ds = norm(p[k + 1] - p[k]);
          const int s = (turn > 0.0) - (turn < 0.0);
          if (s != 0 && sense != 0 && s != sense)
            end_stretch();
          if (s != 0)
            sense = s;
          sweep += turn;
          length += ds;
          total += ds;
        }
      end_stretch();
      return total > 0.0 ? coiled / total : 0.0;
    }

    /// One channel: the fraction of the wire's points whose mirror image
    /// about the line through the inlet and `centre` lies within d/4 of the
    /// wire's centreline (its nodes in a grid of cells as long as its
    /// longest segment, searched 3 x 3). Points placed at random, with the
    /// wire's packing density phi, would score about phi/2 (the band d/2
    /// wide along the centreline covers that fraction of the area).
    double mirror_overlap(const std::vector<Vec2> &p, const Vec2 &inlet, const Vec2 &centre, const double d)
    {
      const Vec2 line = centre - inlet;
      const bool finite = std::all_of(p.begin(), p.end(),
                                      [](const Vec2 &q) { return std::isfinite(q.x) && std::isfinite(q.y); });
      if (p.empty() || norm(line) == 0.0 || !finite)
        return 0.0;
      const Vec2 a = (1.0 / norm(line)) * line;
      double size = d;
      for (std::size_t k = 0; k + 1 < p.size(); ++k)
        size = std::max(size, norm(p[k + 1] - p[k]));
      const auto cell = [size](const Vec2 &q) {
        return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(std::floor(q.x / size)),
                                                     static_cast<std::int64_t>(std::floor(q.y / size))};
      };
      const auto key = [](const std::int64_t i, const std::int64_t j) {
        return static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(j);
      };
      std::unordered_multimap<std::uint64_t, int> grid;
      for (int k = 0; k < static_cast<int>(p.size()); ++k)
        {
          const auto [i, j] = cell(p[k]);
          grid.emplace(key(i, j), k);
        }
      const double reach2 = 0.0625 * d * d; // (d/4)^2
      const auto within = [&](const int a, const Vec2 &q) {
        return contact::closest_on_segment(q, p[a], p[a + 1]).distance2 < reach2;
      };
      int matched = 0;
      for (const auto &q : p)
        {
          const Vec2 r = q - inlet;
          const Vec2 m = inlet + (2.0 * dot(r, a)) * a - r;
          const auto [i, j] = cell(m);
          bool near = false;
          for (std::int64_t di = -1; di <= 1 && !near; ++di)
            for (std::int64_t dj = -1; dj <= 1 && !near; ++dj)
              {
                const auto range = grid.equal_range(key(i + di, j + dj));
                for (auto it = range.first; it != range.second && !near; ++it)
                  {
                    const int k = it->second;
                    near =
                        (k + 1 < static_cast<int>(p.size()) && within(k, m)) || (k > 0 && within(k - 1, m));
                  }
              }
          matched += near;
        }
      return double(matched) / p.size();
    }
  } // namespace

  namespace
  {
    /// Whether p lies inside the closed polygon (crossing number).
    bool inside_polygon(const std::vector<Vec2> &poly, const Vec2 &p)
    {
      bool in = false;
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        {
          const Vec2 a = poly[i], b = poly[j];
          if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
            in = !in;
        }
      return in;
    }

    /// The centroid of the area a closed polygon encloses.
    Vec2 polygon_centroid(const std::vector<Vec2> &poly)
    {
      double twice_area = 0.0;
      Vec2 sum{};
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        {
          const double c = cross(poly[j], poly[i]);
          twice_area += c;
          sum = sum + c * (poly[j] + poly[i]);
        }
      return (1.0 / (3.0 * twice_area)) * sum;
    }
  } // namespace

  Morphology classify(const core::WireState &wire, const double spiral_fraction)
  {
    Morphology m;
    const auto &p = wire.points;
    const int n = static_cast<int>(p.size());
    if (n < 3)
      {
        m.phase = "classic";
        return m;
      }
    // The inner region: the disc of radius r / sqrt(2), or the wall shrunk
    // about its centroid to half the cavity's area.
    const double r_inner = wire.cavity_radius / std::sqrt(2.0);
    const bool shaped = wire.wall.size() >= 3;
    const Vec2 centre = shaped ? polygon_centroid(wire.wall) : Vec2{};
    const auto in_inner = [&](const Vec2 &q) {
      return shaped ? inside_polygon(wire.wall, centre + std::sqrt(2.0) * (q - centre)) : norm(q) < r_inner;
    };
    double a = 0.0, b = 0.0, l_in = 0.0, l_out = 0.0;
    for (int k = 0; k < n; ++k)
      {
        const double kappa = k < static_cast<int>(wire.curvature.size()) ? wire.curvature[k] : 0.0;
        const double ds = (k > 0 && k < n - 1) ? 0.5 * (norm(p[k + 1] - p[k]) + norm(p[k] - p[k - 1])) : 0.0;
        const bool inside = in_inner(p[k]);
        (inside ? a : b) += kappa * kappa * ds;
        (inside ? l_in : l_out) += ds;
      }
    const auto ratio = [](const double x, const double y) {
      return y > 0.0 ? x / y : (x > 0.0 ? INFINITY : 0.0);
    };
    m.curvature_ratio = ratio(a, b);
    m.inner_wire_fraction = l_in + l_out > 0.0 ? l_in / (l_in + l_out) : 0.0;
    m.curvature_density_ratio = ratio(l_in > 0.0 ? a / l_in : 0.0, l_out > 0.0 ? b / l_out : 0.0);

    // Mirror symmetry about the y axis (any other cavity: about the
    // perpendicular bisector of the wire's ends): the k-th point from the
    // left inlet, mirrored, against the k-th point from the right inlet (the
    // models' points are equally spaced along the wire). One channel: how
    // much of the wire its mirror image about the channel's line through
    // the centroid covers.
    double dev = 0.0;
    const int half = n / 2;
    const Vec2 middle = 0.5 * (p[0] + p[n - 1]), ends = p[n - 1] - p[0];
    const Vec2 axis = shaped && norm(ends) > 0.0 ? (1.0 / norm(ends)) * ends : Vec2{1.0, 0.0};
    for (int k = 0; k < half; ++k)
      {
        const Vec2 l = p[k], r = p[n - 1 - k];
        const Vec2 mirrored = shaped ? l - (2.0 * dot(l - middle, axis)) * axis : Vec2{-l.x, l.y};
        dev += norm(mirrored - r);
      }
    const bool one_channel = shaped && wire.channels.size() == 1;
    m.symmetry = std::clamp(1.0 - dev / (half * wire.cavity_radius), 0.0, 1.0);
    if (one_channel)
      m.symmetry = mirror_overlap(p, wire.channels[0].inlet, centre, wire.diameter);

    // Spiral: most of the wire winds round the centre without turning
    // back, in either sense and whether or not it is folded (a coil wound
    // inwards and back out between its turns nets no winding per half).
    const int mid = n / 2;
    m.winding_left = winding(p, 0, mid);
    m.winding_right = winding(p, n - 1, mid);
    m.coiled_fraction = coiled_fraction(p);
    const bool spiral = m.coiled_fraction >= spiral_fraction;
    m.phase = spiral ? "spiral" : (m.curvature_ratio < 0.5 ? "classic" : "plastic");
    return m;
  }
} // namespace wirefem::analysis
