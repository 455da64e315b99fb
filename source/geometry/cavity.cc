#include <wirefem/geometry/cavity.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace wirefem::geometry
{
  namespace
  {
    using core::cross;
    using core::dot;
    using core::norm;
    using core::perp;

    constexpr double two_pi = 2.0 * M_PI;

    /// 8-point Gauss-Legendre rule on [0, 1]: nodes and weights.
    constexpr std::array<double, 8> gauss_x = {{0.019855071751231856, 0.10166676129318664, 0.2372337950418355,
                                                0.4082826787521751, 0.5917173212478249, 0.7627662049581645,
                                                0.8983332387068134, 0.9801449282487681}};
    constexpr std::array<double, 8> gauss_w = {{0.05061426814518813, 0.11119051722668724, 0.15685332293894363,
                                                0.18134189168918100, 0.18134189168918100, 0.15685332293894363,
                                                0.11119051722668724, 0.05061426814518813}};

    /// The speed |dx/dphi| of the ellipse (a cos phi, b sin phi).
    double ellipse_speed(const double a, const double b, const double phi)
    {
      return std::hypot(a * std::sin(phi), b * std::cos(phi));
    }

    /// The angle of v's direction, measured from `start` in the direction of
    /// `sweep`'s sign, in [0, 2 pi).
    double angle_along(const Vec2 &v, const double start, const double sweep)
    {
      double t = std::atan2(v.y, v.x) - start;
      if (sweep < 0.0)
        t = -t;
      t = std::fmod(t, two_pi);
      return t < 0.0 ? t + two_pi : t;
    }

    Vec2 arc_point(const Cavity::Piece &c, const double angle)
    {
      const double r = std::abs(c.radius);
      return {c.centre.x + r * std::cos(angle), c.centre.y + r * std::sin(angle)};
    }

    /// The inward normal of a piece at its point q.
    Vec2 piece_normal(const Cavity::Piece &c, const Vec2 &q)
    {
      if (c.radius == 0.0)
        return perp((1.0 / c.length) * (c.to - c.from));
      const Vec2 out = (1.0 / std::abs(c.radius)) * (q - c.centre);
      return c.radius > 0.0 ? -out : out;
    }

    /// The point of a piece nearest to p.
    Vec2 nearest_on_piece(const Cavity::Piece &c, const Vec2 &p)
    {
      if (c.radius == 0.0)
        {
          const Vec2 e = c.to - c.from;
          const double t = std::clamp(dot(p - c.from, e) / dot(e, e), 0.0, 1.0);
          return c.from + t * e;
        }
      const Vec2 d = p - c.centre;
      if (d.x == 0.0 && d.y == 0.0)
        return c.from;
      if (angle_along(d, c.start, c.sweep) <= std::abs(c.sweep))
        return c.centre + (std::abs(c.radius) / norm(d)) * d;
      return core::norm_square(p - c.from) <= core::norm_square(p - c.to) ? c.from : c.to;
    }

    /// Contributions of a piece to the integrals of 1, x and y over the
    /// enclosed area, by Green's theorem: (1/2) closed integral of
    /// (x dy - y dx), of x^2 dy / 2 and of -y^2 dx / 2.
    std::array<double, 3> green(const Cavity::Piece &c)
    {
      if (c.radius == 0.0)
        {
          const Vec2 a = c.from, e = c.to - c.from;
          return {{0.5 * cross(a, c.to), 0.5 * e.y * (a.x * a.x + a.x * e.x + e.x * e.x / 3.0),
                   -0.5 * e.x * (a.y * a.y + a.y * e.y + e.y * e.y / 3.0)}};
        }
      const double r = std::abs(c.radius);
      std::array<double, 3> s{};
      for (std::size_t k = 0; k < gauss_x.size(); ++k)
        {
          const double phi = c.start + gauss_x[k] * c.sweep, w = gauss_w[k] * c.sweep;
          const Vec2 x = arc_point(c, phi);
          const double dx = -r * std::sin(phi) * w, dy = r * std::cos(phi) * w;
          s[0] += 0.5 * (x.x * dy - x.y * dx);
          s[1] += 0.5 * x.x * x.x * dy;
          s[2] -= 0.5 * x.y * x.y * dx;
        }
      return s;
    }

    /// Faults of a polygon's vertices (counter-clockwise) other than its
    /// corner radius: repeated or collinear neighbours, crossing edges.
    void check_vertices(const std::vector<Vec2> &v)
    {
      const std::size_t n = v.size();
      for (std::size_t i = 0; i < n; ++i)
        {
          const Vec2 u = v[i] - v[(i + n - 1) % n], w = v[(i + 1) % n] - v[i];
          if (w.x == 0.0 && w.y == 0.0)
            throw std::invalid_argument(fmt::format("vertices {} and {} coincide", i + 1, (i + 1) % n + 1));
          if (std::abs(cross(u, w)) <= 1e-12 * norm(u) * norm(w))
            throw std::invalid_argument(fmt::format("vertices {}, {} and {} are collinear",
                                                    (i + n - 1) % n + 1, i + 1, (i + 1) % n + 1));
        }
      using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
      CGAL::Polygon_2<Kernel> polygon;
      for (const auto &p : v)
        polygon.push_back(Kernel::Point_2(p.x, p.y));
      if (!polygon.is_simple())
        throw std::invalid_argument("its edges cross (the polygon is not simple)");
    }
  } // namespace

  Cavity Cavity::circle(const double radius)
  {
    if (!(radius > 0.0) || !std::isfinite(radius))
      throw std::invalid_argument("the radius must be positive");
    Cavity c;
    c.kind = Shape::circle;
    c.a = c.b = radius;
    c.area_ = M_PI * radius * radius;
    c.perimeter_ = two_pi * radius;
    return c;
  }

  Cavity Cavity::ellipse(const double a, const double b)
  {
    if (!(a > 0.0) || !(b > 0.0) || !std::isfinite(a) || !std::isfinite(b))
      throw std::invalid_argument("the semi-axes must be positive");
    Cavity c;
    c.kind = Shape::ellipse;
    c.a = a;
    c.b = b;
    c.build_ellipse();
    return c;
  }

  Cavity Cavity::polygon(std::vector<Vec2> vertices, const double corner_radius)
  {
    if (vertices.size() < 3)
      throw std::invalid_argument(
          fmt::format("a polygon needs at least 3 vertices, not {}", vertices.size()));
    for (const auto &p : vertices)
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        throw std::invalid_argument("a vertex is not a finite number");
    if (!(corner_radius > 0.0) || !std::isfinite(corner_radius))
      throw std::invalid_argument("the corner radius must be positive (the wall must be smooth)");
    double twice_area = 0.0;
    for (std::size_t i = 0; i < vertices.size(); ++i)
      twice_area += cross(vertices[i], vertices[(i + 1) % vertices.size()]);
    if (twice_area < 0.0)
      std::reverse(vertices.begin(), vertices.end());
    check_vertices(vertices);
    Cavity c;
    c.kind = Shape::polygon;
    c.vertices = std::move(vertices);
    c.corner_radius = corner_radius;
    c.build_polygon();
    return c;
  }

  void Cavity::build_polygon()
  {
    const std::size_t n = vertices.size();
    const double r = corner_radius;
    // Each corner's turn and the length of edge its arc takes, r tan(|turn|/2).
    std::vector<double> turn(n), take(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        const Vec2 u = vertices[i] - vertices[(i + n - 1) % n], w = vertices[(i + 1) % n] - vertices[i];
        turn[i] = std::atan2(cross(u, w), dot(u, w));
        take[i] = r * std::tan(0.5 * std::abs(turn[i]));
      }
    for (std::size_t i = 0; i < n; ++i)
      {
        const std::size_t j = (i + 1) % n;
        const double edge = norm(vertices[j] - vertices[i]);
        if (take[i] + take[j] > edge * (1.0 + 1e-12))
          throw std::invalid_argument(fmt::format(
              "the corner radius {:g} is too large: the arcs at vertices {} and {} need {:.4g} of "
              "the edge between them, which is {:.4g} long",
              r, i + 1, j + 1, take[i] + take[j], edge));
      }
    pieces.clear();
    for (std::size_t k = 1; k <= n; ++k)
      {
        // The edge into vertex i, then the arc at vertex i.
        const std::size_t i = k % n, h = k - 1;
        const Vec2 e = vertices[i] - vertices[h];
        const double edge = norm(e);
        const Vec2 u = (1.0 / edge) * e, w = (1.0 / norm(vertices[(i + 1) % n] - vertices[i])) *
                                             (vertices[(i + 1) % n] - vertices[i]);
        const Vec2 from = vertices[h] + take[h] * u, to = vertices[i] - take[i] * u;
        if (edge - take[h] - take[i] > 0.0)
          pieces.push_back({from, to, {}, 0.0, 0.0, 0.0, norm(to - from)});
        Piece arc;
        arc.from = to;
        arc.to = vertices[i] + take[i] * w;
        arc.radius = turn[i] > 0.0 ? r : -r;
        arc.centre = to + (turn[i] > 0.0 ? r : -r) * perp(u);
        arc.start = std::atan2(to.y - arc.centre.y, to.x - arc.centre.x);
        arc.sweep = turn[i];
        arc.length = r * std::abs(turn[i]);
        pieces.push_back(arc);
      }
    std::array<double, 3> s{};
    perimeter_ = 0.0;
    for (const auto &c : pieces)
      {
        const auto g = green(c);
        for (int m = 0; m < 3; ++m)
          s[m] += g[m];
        perimeter_ += c.length;
      }
    area_ = s[0];
    centroid_ = {s[1] / s[0], s[2] / s[0]};
    build_grid();
    inradius_ = std::max(0.0, nearest_on_polygon(centroid_).depth);
  }

  int Cavity::Grid::index(const Vec2 &p) const
  {
    const double fx = (p.x - origin.x) / cell, fy = (p.y - origin.y) / cell;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < nx && fy < ny))
      return -1;
    return static_cast<int>(fy) * nx + static_cast<int>(fx);
  }

  void Cavity::build_grid()
  {
    // Cells of twice the corner radius, or of 1/256 of the perimeter if
    // that is longer, over the wall's box grown by a cell.
    Vec2 lo = pieces[0].from, hi = lo;
    for (const auto &c : pieces)
      for (const Vec2 &q : {c.from, c.to})
        {
          lo = {std::min(lo.x, q.x), std::min(lo.y, q.y)};
          hi = {std::max(hi.x, q.x), std::max(hi.y, q.y)};
        }
    Grid g;
    g.cell = std::max(2.0 * corner_radius, perimeter_ / 256.0);
    g.origin = lo - Vec2{g.cell, g.cell};
    g.nx = static_cast<int>(std::ceil((hi.x - lo.x) / g.cell)) + 2;
    g.ny = static_cast<int>(std::ceil((hi.y - lo.y) / g.cell)) + 2;
    // Each piece's box (an arc's: its circle's), grown by a cell, bounds the
    // cells it may list in; pieces in order, so each cell lists them in order.
    std::vector<std::vector<int>> lists(static_cast<std::size_t>(g.nx) * g.ny);
    for (std::size_t k = 0; k < pieces.size(); ++k)
      {
        const auto &c = pieces[k];
        const double rr = std::abs(c.radius);
        Vec2 a =
            rr > 0.0 ? c.centre - Vec2{rr, rr} : Vec2{std::min(c.from.x, c.to.x), std::min(c.from.y, c.to.y)};
        Vec2 b =
            rr > 0.0 ? c.centre + Vec2{rr, rr} : Vec2{std::max(c.from.x, c.to.x), std::max(c.from.y, c.to.y)};
        a = a - Vec2{g.cell, g.cell} - g.origin;
        b = b + Vec2{g.cell, g.cell} - g.origin;
        const int i0 = std::max(0, static_cast<int>(std::floor(a.x / g.cell)));
        const int j0 = std::max(0, static_cast<int>(std::floor(a.y / g.cell)));
        const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor(b.x / g.cell)));
        const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor(b.y / g.cell)));
        // Of those, the cells whose centre is within a cell and half the
        // cell's diagonal of the piece: any point of the cell within a cell
        // of the piece is (a long slanted edge's box would list far more).
        const double reach = g.cell * (1.0 + 0.5 * std::sqrt(2.0));
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i)
            {
              const Vec2 centre = g.origin + Vec2{(i + 0.5) * g.cell, (j + 0.5) * g.cell};
              if (norm(centre - nearest_on_piece(c, centre)) <= reach)
                lists[static_cast<std::size_t>(j) * g.nx + i].push_back(static_cast<int>(k));
            }
      }
    g.cell_start.assign(lists.size() + 1, 0);
    g.inside.assign(lists.size(), 0);
    for (std::size_t i = 0; i < lists.size(); ++i)
      {
        g.cell_start[i + 1] = g.cell_start[i] + static_cast<int>(lists[i].size());
        g.cell_pieces.insert(g.cell_pieces.end(), lists[i].begin(), lists[i].end());
      }
    // A cell without pieces is wholly on one side of the wall: its centre's.
    grid = Grid{};
    for (std::size_t i = 0; i < lists.size(); ++i)
      if (lists[i].empty())
        {
          const Vec2 centre = g.origin + Vec2{(static_cast<double>(i % g.nx) + 0.5) * g.cell,
                                              (static_cast<double>(i / g.nx) + 0.5) * g.cell};
          g.inside[i] = nearest_on_polygon(centre).depth > 0.0;
        }
    grid = std::move(g);
  }

  void Cavity::build_ellipse()
  {
    // Arc length against the parameter angle, by Gauss-Legendre on each
    // of n intervals (the speed is smooth: exact to round-off).
    const int n = 1024;
    arc_table.assign(n + 1, 0.0);
    for (int k = 0; k < n; ++k)
      {
        double s = 0.0;
        for (std::size_t q = 0; q < gauss_x.size(); ++q)
          {
            const double phi = two_pi * (k + gauss_x[q]) / n;
            s += gauss_w[q] * ellipse_speed(a, b, phi);
          }
        arc_table[k + 1] = arc_table[k] + s * two_pi / n;
      }
    area_ = M_PI * a * b;
    perimeter_ = arc_table.back();
    centroid_ = {0.0, 0.0};
  }

  WallPoint Cavity::nearest(const Vec2 &p) const
  {
    switch (kind)
      {
      case Shape::circle:
        {
          const double r = norm(p);
          const Vec2 out = r > 0.0 ? (1.0 / r) * p : Vec2{1.0, 0.0};
          return {a * out, -out, a - r, 1.0 / a};
        }
      case Shape::ellipse:
        return nearest_on_ellipse(p);
      case Shape::polygon:
        return nearest_on_polygon(p);
      }
    return {};
  }

  bool Cavity::surely_deeper(const Vec2 &p, const double delta) const
  {
    switch (kind)
      {
      case Shape::circle:
        return a > delta && core::norm_square(p) < (a - delta) * (a - delta);
      case Shape::ellipse:
        {
          const double s = 1.0 - delta / std::min(a, b);
          return s > 0.0 && (p.x / a) * (p.x / a) + (p.y / b) * (p.y / b) < s * s;
        }
      case Shape::polygon:
        break;
      }
    const double r = inradius_ - delta;
    if (r > 0.0 && core::norm_square(p - centroid_) < r * r)
      return true;
    const int i = grid.index(p);
    return i >= 0 && grid.cell >= delta && grid.cell_start[i] == grid.cell_start[i + 1] && grid.inside[i];
  }

  WallPoint Cavity::nearest_on_polygon(const Vec2 &p) const
  {
    std::size_t best = 0;
    Vec2 q;
    double d2 = INFINITY;
    const auto consider = [&](const std::size_t k) {
      const Vec2 qk = nearest_on_piece(pieces[k], p);
      const double dk = core::norm_square(p - qk);
      if (dk < d2)
        best = k, q = qk, d2 = dk;
    };
    // The pieces of p's cell, in the wall's order: the nearest of all if
    // it lies within a cell size (grid, above); else all of them.
    const int i = grid.cell_start.empty() ? -1 : grid.index(p);
    if (i >= 0)
      for (int c = grid.cell_start[i]; c < grid.cell_start[i + 1]; ++c)
        consider(static_cast<std::size_t>(grid.cell_pieces[c]));
    if (!(d2 <= grid.cell * grid.cell))
      {
        d2 = INFINITY;
        for (std::size_t k = 0; k < pieces.size(); ++k)
          consider(k);
      }
    const Vec2 n = piece_normal(pieces[best], q);
    const double radius = pieces[best].radius;
    return {q, n, dot(p - q, n), radius == 0.0 ? 0.0 : 1.0 / radius};
  }

  WallPoint Cavity::nearest_on_ellipse(const Vec2 &p) const
  {
    // In the first quadrant with e0 >= e1 (axes swapped if needed), the
    // nearest point is x_i = e_i^2 y_i / (t + e_i^2) for the root t of
    // sum (e_i y_i / (t + e_i^2))^2 = 1; in scaled form s = t / e1^2, a
    // convex decreasing function, found by Newton from a point left of
    // the root (monotone, no overshoot).
    const bool swap = a < b;
    const double e0 = swap ? b : a, e1 = swap ? a : b;
    const double y0 = std::abs(swap ? p.y : p.x), y1 = std::abs(swap ? p.x : p.y);
    double x0, x1;
    if (y1 > 0.0 && y0 > 0.0)
      {
        // Newton in u = s + 1 > 0, which starts at u = z1 exactly: in s
        // the start z1 - 1 rounds to -1 when y1 is tiny.
        const double z0 = y0 / e0, z1 = y1 / e1, r0 = (e0 / e1) * (e0 / e1), n0 = r0 * z0;
        const double r1 = (e0 - e1) * (e0 + e1) / (e1 * e1); // r0 - 1
        double u = z1;
        for (int it = 0; it < 100; ++it)
          {
            const double g0 = n0 / (u + r1), g1 = z1 / u;
            const double g = g0 * g0 + g1 * g1 - 1.0;
            const double dg = -2.0 * (g0 * g0 / (u + r1) + g1 * g1 / u);
            const double next = u - g / dg;
            if (!(next > u) || g <= 0.0)
              break;
            u = next;
          }
        x0 = r0 * y0 / (u + r1);
        x1 = y1 / u;
      }
    else if (y1 > 0.0)
      x0 = 0.0, x1 = e1;
    else
      {
        const double numer = e0 * y0, denom = e0 * e0 - e1 * e1;
        if (numer < denom)
          {
            const double xd = numer / denom;
            x0 = e0 * xd;
            x1 = e1 * std::sqrt(std::max(0.0, 1.0 - xd * xd));
          }
        else
          x0 = e0, x1 = 0.0;
      }
    // Back to p's quadrant and axes.
    const double sx = (swap ? p.y : p.x) < 0.0 ? -1.0 : 1.0, sy = (swap ? p.x : p.y) < 0.0 ? -1.0 : 1.0;
    Vec2 q{sx * x0, sy * x1}, out{sx * x0 / (e0 * e0), sy * x1 / (e1 * e1)};
    if (swap)
      q = {q.y, q.x}, out = {out.y, out.x};
    const Vec2 n = (-1.0 / norm(out)) * out;
    // kappa = a b / |dx/dphi|^3 at the parameter angle of q.
    const double speed = std::hypot(a * q.y / b, b * q.x / a);
    return {q, n, dot(p - q, n), a * b / (speed * speed * speed)};
  }

  WallPoint Cavity::at(const double s_in) const
  {
    double s = std::fmod(s_in, perimeter_);
    if (s < 0.0)
      s += perimeter_;
    if (kind == Shape::circle)
      {
        const Vec2 out{std::cos(s / a), std::sin(s / a)};
        return {a * out, -out, 0.0};
      }
    if (kind == Shape::ellipse)
      {
        // The table's interval, then Newton on the parameter angle.
        const auto it = std::upper_bound(arc_table.begin(), arc_table.end(), s);
        const auto k = std::clamp<std::ptrdiff_t>(it - arc_table.begin() - 1, 0,
                                                  static_cast<std::ptrdiff_t>(arc_table.size()) - 2);
        const double step = two_pi / static_cast<double>(arc_table.size() - 1);
        double phi =
            step * static_cast<double>(k) + step * (s - arc_table[k]) / (arc_table[k + 1] - arc_table[k]);
        const double lo = step * static_cast<double>(k);
        const auto speed = [&](const double t) { return ellipse_speed(a, b, t); };
        for (int i = 0; i < 3; ++i)
          {
            // The arc length from the interval's start by Simpson's rule:
            // the interval is short, so three iterations reach round-off.
            const double arc =
                arc_table[k] + (phi - lo) / 6.0 * (speed(lo) + 4.0 * speed(0.5 * (lo + phi)) + speed(phi));
            phi -= (arc - s) / speed(phi);
          }
        const Vec2 q{a * std::cos(phi), b * std::sin(phi)}, out{q.x / (a * a), q.y / (b * b)};
        return {q, (-1.0 / norm(out)) * out, 0.0};
      }
    for (const auto &c : pieces)
      {
        if (s <= c.length || &c == &pieces.back())
          {
            const double f = std::min(s, c.length);
            const Vec2 q =
                c.radius == 0.0
                    ? c.from + (f / c.length) * (c.to - c.from)
                    : arc_point(c, c.start + (c.sweep > 0.0 ? 1.0 : -1.0) * f / std::abs(c.radius));
            return {q, piece_normal(c, q), 0.0};
          }
        s -= c.length;
      }
    return {};
  }

  std::vector<Vec2> Cavity::outline(const int n) const
  {
    std::vector<Vec2> points;
    for (int k = 0; k < std::max(n, 3); ++k)
      points.push_back(at(perimeter_ * k / std::max(n, 3)).point);
    return points;
  }

  Cavity Cavity::scaled(const double factor) const
  {
    if (!(factor > 0.0))
      throw std::invalid_argument("the scale factor must be positive");
    switch (kind)
      {
      case Shape::circle:
        return circle(factor * a);
      case Shape::ellipse:
        return ellipse(factor * a, factor * b);
      case Shape::polygon:
        break;
      }
    std::vector<Vec2> v;
    for (const auto &p : vertices)
      v.push_back(centroid_ + factor * (p - centroid_));
    return polygon(std::move(v), factor * corner_radius);
  }
} // namespace wirefem::geometry
