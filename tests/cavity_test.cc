// The cavity's wall shapes (geometry::Cavity) against brute force: nearest
// points, normals and signed distances on random points, arc length,
// area and centroid; the ellipse of aspect 1 against the circle; faulty
// polygons refused with the fault named.
#include <wirefem/geometry/cavity.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  using namespace wirefem;
  using geometry::Cavity;
  using geometry::Vec2;

  /// The wall as a dense polyline of n points, through Cavity::at.
  std::vector<Vec2> sampled(const Cavity &c, const int n)
  {
    std::vector<Vec2> w(n);
    for (int k = 0; k < n; ++k)
      w[k] = c.at(c.perimeter() * k / n).point;
    return w;
  }

  /// Distance from p to the polyline, and whether p lies inside it (the
  /// winding number).
  std::pair<double, bool> brute_force(const std::vector<Vec2> &w, const Vec2 &p)
  {
    double best = INFINITY;
    int winding = 0;
    for (std::size_t k = 0; k < w.size(); ++k)
      {
        const Vec2 a = w[k], b = w[(k + 1) % w.size()], e = b - a;
        const double t = std::clamp(core::dot(p - a, e) / core::dot(e, e), 0.0, 1.0);
        best = std::min(best, core::norm(p - (a + t * e)));
        if (a.y <= p.y && b.y > p.y && core::cross(e, p - a) > 0)
          ++winding;
        if (a.y > p.y && b.y <= p.y && core::cross(e, p - a) < 0)
          --winding;
      }
    return {best, winding != 0};
  }

  /// A wavy 96-gon, radius 10 + 1.5 sin(6 theta) (reflex corners too):
  /// many short pieces, each cell of the polygon's grid lists a few.
  std::vector<Vec2> wavy()
  {
    std::vector<Vec2> v;
    for (int k = 0; k < 96; ++k)
      {
        const double t = 2.0 * M_PI * k / 96, rho = 10.0 + 1.5 * std::sin(6.0 * t);
        v.push_back({rho * std::cos(t), rho * std::sin(t)});
      }
    return v;
  }

  /// The shapes under test: two ellipses (one taller than wide), a rounded
  /// square, a rounded L (a reflex corner), a rounded triangle given
  /// clockwise and a wavy many-sided polygon.
  std::vector<std::pair<std::string, Cavity>> shapes()
  {
    return {{"wavy 96-gon", Cavity::polygon(wavy(), 1.0)},
            {"ellipse 1.5", Cavity::ellipse(15.0, 10.0)},
            {"ellipse 2, tall", Cavity::ellipse(8.0, 16.0)},
            {"rounded square", Cavity::polygon({{-10, -10}, {10, -10}, {10, 10}, {-10, 10}}, 3.0)},
            {"rounded L", Cavity::polygon({{0, 0}, {20, 0}, {20, 8}, {8, 8}, {8, 20}, {0, 20}}, 2.0)},
            {"triangle, clockwise", Cavity::polygon({{0, 0}, {5, 18}, {20, 2}}, 1.5)}};
  }

  TEST(Cavity, NearestWallPointMatchesBruteForce)
  {
    std::mt19937 rng(7);
    for (const auto &[name, c] : shapes())
      {
        const auto wall = sampled(c, 100000);
        std::uniform_real_distribution<double> x(-25.0, 25.0);
        double worst_distance = 0.0, worst_projection = 0.0, worst_unit = 0.0;
        int wrong_side = 0;
        for (int k = 0; k < 500; ++k)
          {
            const Vec2 p{x(rng), x(rng)};
            const auto w = c.nearest(p);
            const auto [distance, inside] = brute_force(wall, p);
            worst_distance = std::max(worst_distance, std::abs(std::abs(w.depth) - distance));
            wrong_side += (w.depth > 0.0) != inside;
            // p lies on the wall's normal through its nearest point.
            worst_projection = std::max(worst_projection, core::norm(p - (w.point + w.depth * w.normal)));
            worst_unit = std::max(worst_unit, std::abs(core::norm(w.normal) - 1.0));
          }
        EXPECT_LT(worst_distance, 1e-6) << name;
        EXPECT_EQ(wrong_side, 0) << name;
        EXPECT_LT(worst_projection, 1e-9) << name;
        EXPECT_LT(worst_unit, 1e-12) << name;
      }
  }

  TEST(Cavity, WallPointsByArcLengthLieOnTheWallWithTheirNormal)
  {
    // at(s): on the wall, its normal the left-hand perpendicular of the
    // wall's direction (counter-clockwise), and the arc length between
    // neighbouring points their distance.
    for (const auto &[name, c] : shapes())
      {
        const int n = 20000;
        const double ds = c.perimeter() / n;
        double worst_on = 0.0, worst_normal = 0.0, worst_arc = 0.0;
        for (int k = 0; k < n; ++k)
          {
            const auto w = c.at(k * ds), next = c.at((k + 1) * ds);
            worst_on = std::max(worst_on, std::abs(c.nearest(w.point).depth));
            const double eps = 1e-5;
            const Vec2 direction = (0.5 / eps) * (c.at(k * ds + eps).point - c.at(k * ds - eps).point);
            worst_normal = std::max(worst_normal, core::norm(w.normal - core::perp(direction)));
            worst_arc = std::max(worst_arc, std::abs(core::norm(next.point - w.point) - ds) / ds);
          }
        EXPECT_LT(worst_on, 1e-9) << name;
        EXPECT_LT(worst_normal, 1e-4) << name;
        EXPECT_LT(worst_arc, 1e-4) << name;
        EXPECT_LT(core::norm(c.at(c.perimeter()).point - c.at(0.0).point), 1e-9) << name;
      }
  }

  TEST(Cavity, AreaCentroidAndPerimeter)
  {
    // Closed forms, and the perimeter of a polyline of 1e6 points.
    const double side = 20.0, r = 3.0;
    const auto square = Cavity::polygon({{0, 0}, {side, 0}, {side, side}, {0, side}}, r);
    EXPECT_NEAR(square.area(), side * side - (4.0 - M_PI) * r * r, 1e-10);
    EXPECT_NEAR(square.perimeter(), 4.0 * side - 8.0 * r + 2.0 * M_PI * r, 1e-10);
    EXPECT_NEAR(square.centroid().x, 0.5 * side, 1e-10);
    EXPECT_NEAR(square.centroid().y, 0.5 * side, 1e-10);
    // The L: two rectangles, corners cut and the reflex corner filled.
    const auto l_shape = Cavity::polygon({{0, 0}, {20, 0}, {20, 8}, {8, 8}, {8, 20}, {0, 20}}, 2.0);
    EXPECT_NEAR(l_shape.area(), 20.0 * 8.0 + 8.0 * 12.0 - 5.0 * (4.0 - M_PI) + (4.0 - M_PI), 1e-10);
    const auto ellipse = Cavity::ellipse(20.0, 10.0);
    EXPECT_NEAR(ellipse.area(), M_PI * 200.0, 1e-10);
    double polyline = 0.0;
    const int n = 1000000;
    for (int k = 0; k < n; ++k)
      {
        const double t0 = 2 * M_PI * k / n, t1 = 2 * M_PI * (k + 1) / n;
        polyline += std::hypot(20.0 * (std::cos(t1) - std::cos(t0)), 10.0 * (std::sin(t1) - std::sin(t0)));
      }
    EXPECT_NEAR(ellipse.perimeter() / polyline, 1.0, 1e-10);
  }

  TEST(Cavity, EllipseOfAspectOneIsTheCircle)
  {
    const auto circle = Cavity::circle(12.5), round = Cavity::ellipse(12.5, 12.5);
    EXPECT_NEAR(round.area(), circle.area(), 1e-10);
    EXPECT_NEAR(round.perimeter(), circle.perimeter(), 1e-10);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> x(-20.0, 20.0);
    for (int k = 0; k < 1000; ++k)
      {
        const Vec2 p{x(rng), x(rng)};
        const auto a = circle.nearest(p), b = round.nearest(p);
        EXPECT_NEAR(a.depth, b.depth, 1e-10);
        EXPECT_LT(core::norm(a.point - b.point), 1e-10);
        EXPECT_LT(core::norm(a.normal - b.normal), 1e-10);
        const double s = circle.perimeter() * k / 1000.0;
        EXPECT_LT(core::norm(circle.at(s).point - round.at(s).point), 1e-9);
      }
  }

  TEST(Cavity, CurvatureIsTheTurnOfTheNormalPerLength)
  {
    // Between two wall points close together the normal turns by the
    // curvature times the arc (positive where the wall bends round the
    // cavity), on every piece of every shape.
    for (const auto &[name, c] : shapes())
      for (int k = 0; k < 200; ++k)
        {
          const double s = c.perimeter() * (k + 0.5) / 200.0, e = 1e-5;
          const auto a = c.at(s - e), b = c.at(s + e);
          const double turn = std::atan2(core::cross(a.normal, b.normal), core::dot(a.normal, b.normal));
          const double kappa = c.nearest(c.at(s).point).curvature;
          EXPECT_NEAR(turn / (2.0 * e), kappa, 1e-4 * (1.0 + std::abs(kappa))) << name << " at s = " << s;
        }
  }

  TEST(Cavity, SurelyDeeperPointsAreDeeper)
  {
    // Never a false yes; and most points well inside are recognised
    // without nearest() (the test's purpose: the wall term skips them).
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> x(-20.0, 20.0);
    for (const auto &[name, c] : shapes())
      for (const double delta : {0.5, 2.0})
        {
          int deep = 0, recognised = 0;
          for (int k = 0; k < 20000; ++k)
            {
              const Vec2 p{x(rng), x(rng)};
              const double depth = c.nearest(p).depth;
              const bool sure = c.surely_deeper(p, delta);
              if (sure)
                {
                  EXPECT_GT(depth, delta) << name << " at " << p.x << ", " << p.y;
                }
              if (depth > delta + 3.0)
                ++deep, recognised += sure;
            }
          if (name.rfind("ellipse", 0) == 0)
            {
              EXPECT_GT(recognised, 0.8 * deep) << name;
            }
        }
    EXPECT_TRUE(Cavity::circle(10.0).surely_deeper({0.0, 9.4}, 0.5));
    EXPECT_FALSE(Cavity::circle(10.0).surely_deeper({0.0, 9.6}, 0.5));
  }

  TEST(Cavity, EllipsePointsBesideItsAxesAreAsOnThem)
  {
    // A point a rounding error off an axis (the initial wire of a run lies
    // on the x axis) has the nearest wall point of the point on the axis,
    // or of its mirror image where the nearest point is off the axis.
    const auto e = Cavity::ellipse(12.25, 8.16);
    for (const double x : {-11.0, -4.04, 0.5, 7.0})
      for (const double y : {4.5e-16, -4.5e-16, 1e-300, 1e-12})
        {
          const auto on = e.nearest({x, 0.0}), beside = e.nearest({x, y});
          EXPECT_NEAR(beside.depth, on.depth, 1e-9) << x << ", " << y;
          EXPECT_NEAR(std::abs(beside.point.y), std::abs(on.point.y), 1e-6) << x << ", " << y;
          EXPECT_NEAR(beside.point.x, on.point.x, 1e-9) << x << ", " << y;
        }
    for (const double y : {-6.0, 3.0})
      for (const double x : {4.5e-16, -1e-13})
        EXPECT_NEAR(e.nearest({x, y}).depth, e.nearest({0.0, y}).depth, 1e-9);
  }

  TEST(Cavity, ScaledHalvesTheAreaAboutTheCentroid)
  {
    for (const auto &[name, c] : shapes())
      {
        const auto inner = c.scaled(1.0 / std::sqrt(2.0));
        EXPECT_NEAR(inner.area(), 0.5 * c.area(), 1e-9 * c.area()) << name;
        EXPECT_LT(core::norm(inner.centroid() - c.centroid()), 1e-9) << name;
      }
  }

  /// The message of the std::invalid_argument that building throws.
  template <typename F>
  std::string fault(F build)
  {
    try
      {
        build();
      }
    catch (const std::invalid_argument &e)
      {
        return e.what();
      }
    return "no error";
  }

  TEST(Cavity, FaultyPolygonsAreRefusedWithTheirFault)
  {
    EXPECT_NE(fault([] {
                Cavity::polygon({{0, 0}, {10, 10}, {10, 0}, {0, 10}}, 1.0);
              }).find("cross"),
              std::string::npos);
    EXPECT_NE(fault([] {
                Cavity::polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 6.0);
              }).find("too large"),
              std::string::npos);
    EXPECT_NE(fault([] {
                Cavity::polygon({{0, 0}, {10, 0}, {10, 0}, {0, 10}}, 1.0);
              }).find("coincide"),
              std::string::npos);
    EXPECT_NE(fault([] {
                Cavity::polygon({{0, 0}, {5, 0}, {10, 0}, {0, 10}}, 1.0);
              }).find("collinear"),
              std::string::npos);
    EXPECT_NE(fault([] { Cavity::polygon({{0, 0}, {10, 0}}, 1.0); }).find("at least 3"), std::string::npos);
    EXPECT_NE(fault([] {
                Cavity::polygon({{0, 0}, {10, 0}, {0, 10}}, 0.0);
              }).find("positive"),
              std::string::npos);
    EXPECT_NE(fault([] { Cavity::ellipse(10.0, -1.0); }).find("positive"), std::string::npos);
    // A square of side 10 takes corner radii up to 5.
    EXPECT_EQ(fault([] { Cavity::polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 5.0); }), "no error");
  }
} // namespace
