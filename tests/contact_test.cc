#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/segment_distance.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
  using wirefem::contact::BroadPhase;
  using wirefem::contact::closest_points;
  using wirefem::contact::ClosestPoints;
  using wirefem::contact::SegmentPair;
  using wirefem::core::Vec2;

  constexpr double tol = 1e-12;
  const double two_pi = 2.0 * std::acos(-1.0);

  void expect_vec_near(const Vec2 &a, const Vec2 &b, const double eps = tol)
  {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
  }

  // Closest points must be consistent with their parameters and lie in range.
  void expect_consistent(const ClosestPoints &c, const Vec2 &a0, const Vec2 &a1, const Vec2 &b0,
                         const Vec2 &b1)
  {
    EXPECT_GE(c.s, 0.0);
    EXPECT_LE(c.s, 1.0);
    EXPECT_GE(c.t, 0.0);
    EXPECT_LE(c.t, 1.0);
    expect_vec_near(c.p, a0 + c.s * (a1 - a0));
    expect_vec_near(c.q, b0 + c.t * (b1 - b0));
    EXPECT_NEAR(c.distance, wirefem::core::norm(c.p - c.q), tol);
  }

  TEST(SegmentDistance, Crossing)
  {
    const Vec2 a0{0, 0}, a1{2, 2}, b0{0, 2}, b1{2, 0};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_EQ(c.distance, 0.0);
    EXPECT_NEAR(c.s, 0.5, tol);
    EXPECT_NEAR(c.t, 0.5, tol);
    expect_vec_near(c.p, {1, 1});
    expect_vec_near(c.q, {1, 1});
  }

  TEST(SegmentDistance, CrossingAsymmetric)
  {
    const Vec2 a0{0, 0}, a1{4, 0}, b0{1, -1}, b1{1, 3};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_EQ(c.distance, 0.0);
    EXPECT_NEAR(c.s, 0.25, tol);
    EXPECT_NEAR(c.t, 0.25, tol);
  }

  TEST(SegmentDistance, ParallelOffset)
  {
    const Vec2 a0{0, 0}, a1{2, 0}, b0{1, 1}, b1{3, 1};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 1.0, tol);
    expect_consistent(c, a0, a1, b0, b1);
    // The chosen pair must be one of the equally close ones: q straight above p.
    EXPECT_NEAR(c.p.x, c.q.x, tol);
    EXPECT_GE(c.p.x, 1.0 - tol);
    EXPECT_LE(c.p.x, 2.0 + tol);
    // Deterministic: the same input gives bit-identical output.
    const auto d = closest_points(a0, a1, b0, b1);
    EXPECT_EQ(c.s, d.s);
    EXPECT_EQ(c.t, d.t);
  }

  TEST(SegmentDistance, ParallelOffsetNoOverlap)
  {
    const Vec2 a0{0, 0}, a1{1, 0}, b0{4, 4}, b1{6, 4};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 5.0, tol);
    EXPECT_EQ(c.s, 1.0);
    EXPECT_EQ(c.t, 0.0);
  }

  TEST(SegmentDistance, CollinearOverlapping)
  {
    const Vec2 a0{0, 0}, a1{3, 0}, b0{1, 0}, b1{5, 0};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 0.0, tol);
    expect_consistent(c, a0, a1, b0, b1);
    EXPECT_GE(c.p.x, 1.0 - tol);
    EXPECT_LE(c.p.x, 3.0 + tol);

    // Reversed direction of one segment.
    const auto d = closest_points(a0, a1, b1, b0);
    EXPECT_NEAR(d.distance, 0.0, tol);
    expect_consistent(d, a0, a1, b1, b0);
  }

  TEST(SegmentDistance, CollinearDisjoint)
  {
    const Vec2 a0{0, 0}, a1{1, 1}, b0{3, 3}, b1{2, 2};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, std::sqrt(2.0), tol);
    EXPECT_EQ(c.s, 1.0);
    EXPECT_EQ(c.t, 1.0);
  }

  TEST(SegmentDistance, EndPointToInterior)
  {
    const Vec2 a0{0, 0}, a1{4, 0}, b0{1, 3}, b1{1, 0.5};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 0.5, tol);
    EXPECT_NEAR(c.s, 0.25, tol);
    EXPECT_EQ(c.t, 1.0);
    expect_consistent(c, a0, a1, b0, b1);
  }

  TEST(SegmentDistance, EndPointTouchingInterior)
  {
    const Vec2 a0{0, 0}, a1{4, 0}, b0{2, 3}, b1{2, 0};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 0.0, tol);
    EXPECT_NEAR(c.s, 0.5, tol);
    EXPECT_EQ(c.t, 1.0);
  }

  TEST(SegmentDistance, EndPointToEndPoint)
  {
    const Vec2 a0{0, 0}, a1{1, 0}, b0{4, 4}, b1{6, 7};
    const auto c = closest_points(a0, a1, b0, b1);
    EXPECT_NEAR(c.distance, 5.0, tol);
    EXPECT_EQ(c.s, 1.0);
    EXPECT_EQ(c.t, 0.0);
    expect_vec_near(c.p, a1);
    expect_vec_near(c.q, b0);
  }

  TEST(SegmentDistance, DegeneratePointSegment)
  {
    const Vec2 p{1, 2}, b0{0, 0}, b1{4, 0};
    const auto c = closest_points(p, p, b0, b1);
    EXPECT_NEAR(c.distance, 2.0, tol);
    EXPECT_NEAR(c.t, 0.25, tol);
    expect_consistent(c, p, p, b0, b1);

    const auto d = closest_points(b0, b1, p, p);
    EXPECT_NEAR(d.distance, 2.0, tol);
    EXPECT_NEAR(d.s, 0.25, tol);
    expect_consistent(d, b0, b1, p, p);

    // Both segments points; also a point on the other segment.
    const Vec2 r{4, 6};
    const auto e = closest_points(p, p, r, r);
    EXPECT_NEAR(e.distance, 5.0, tol);
    EXPECT_TRUE(std::isfinite(e.s) && std::isfinite(e.t));
    const auto f = closest_points(Vec2{2, 0}, Vec2{2, 0}, b0, b1);
    EXPECT_NEAR(f.distance, 0.0, tol);

    // Nearly degenerate: no division blows up.
    const auto g = closest_points(p, p + Vec2{1e-300, 0}, b0, b1);
    EXPECT_NEAR(g.distance, 2.0, tol);
    EXPECT_TRUE(std::isfinite(g.s) && std::isfinite(g.t));
  }

  TEST(SegmentDistance, SymmetryUnderSwap)
  {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int n = 0; n < 1000; ++n)
      {
        const Vec2 a0{u(rng), u(rng)}, a1{u(rng), u(rng)};
        const Vec2 b0{u(rng), u(rng)}, b1{u(rng), u(rng)};
        const auto c = closest_points(a0, a1, b0, b1);
        const auto d = closest_points(b0, b1, a0, a1);
        expect_consistent(c, a0, a1, b0, b1);
        EXPECT_NEAR(c.distance, d.distance, tol);
        // Generic configurations have a unique closest pair.
        EXPECT_NEAR(c.s, d.t, 1e-9);
        EXPECT_NEAR(c.t, d.s, 1e-9);
      }
  }

  // Reference by dense sampling: closest_points is never beaten.
  TEST(SegmentDistance, NotBeatenBySampling)
  {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int n = 0; n < 200; ++n)
      {
        const Vec2 a0{u(rng), u(rng)}, a1{u(rng), u(rng)};
        const Vec2 b0{u(rng), u(rng)}, b1{u(rng), u(rng)};
        const double dist = closest_points(a0, a1, b0, b1).distance;
        double sampled = std::numeric_limits<double>::max();
        for (int i = 0; i <= 100; ++i)
          for (int j = 0; j <= 100; ++j)
            sampled = std::min(sampled, wirefem::core::norm((a0 + (i / 100.0) * (a1 - a0)) -
                                                            (b0 + (j / 100.0) * (b1 - b0))));
        EXPECT_LE(dist, sampled + tol);
        EXPECT_GE(dist, sampled - 0.05);
      }
  }

  // The boxes' gap never exceeds the distance (random pairs, some far
  // apart), and it is the distance for segments side by side along an axis.
  TEST(SegmentDistance, BoxGapIsALowerBoundThatIsTightSideBySide)
  {
    using wirefem::contact::box_gap;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-2.0, 2.0), shift(-6.0, 6.0);
    int separated = 0;
    for (int n = 0; n < 2000; ++n)
      {
        const Vec2 o{shift(rng), shift(rng)};
        const Vec2 a0{u(rng), u(rng)}, a1{u(rng), u(rng)};
        const Vec2 b0 = o + Vec2{u(rng), u(rng)}, b1 = o + Vec2{u(rng), u(rng)};
        const double gap = box_gap(a0, a1, b0, b1);
        EXPECT_LE(gap, closest_points(a0, a1, b0, b1).distance + 1e-14);
        EXPECT_DOUBLE_EQ(gap, box_gap(b1, b0, a1, a0));
        separated += gap > 0.0;
      }
    EXPECT_GT(separated, 500); // the bound is exercised where it matters
    // Two vertical segments 1.5 apart with overlapping heights: gap = distance.
    EXPECT_DOUBLE_EQ(box_gap({0.0, 0.0}, {0.0, 2.0}, {1.5, 1.0}, {1.5, 3.0}), 1.5);
    EXPECT_DOUBLE_EQ(box_gap({0.0, 2.0}, {0.0, 0.0}, {-1.0, -0.5}, {1.0, -0.5}), 0.5);
    EXPECT_LT(box_gap({0.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}, {2.0, 0.0}), 0.0); // crossing
  }

  // d distance / d(a0, a1, b0, b1) = n (1-s), n s, -n (1-t), -n t with
  // n = (p - q) / |p - q|, using the s, t the code returns.
  TEST(SegmentDistance, GradientMatchesFiniteDifference)
  {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    int checked = 0;
    while (checked < 20)
      {
        std::array<double, 8> v;
        for (double &c : v)
          c = u(rng);
        auto dist = [](const std::array<double, 8> &w) {
          return closest_points({w[0], w[1]}, {w[2], w[3]}, {w[4], w[5]}, {w[6], w[7]}).distance;
        };
        const auto c = closest_points({v[0], v[1]}, {v[2], v[3]}, {v[4], v[5]}, {v[6], v[7]});
        if (c.distance < 0.1)
          continue; // crossing or nearly so: not differentiable
        ++checked;

        const Vec2 n = (1.0 / c.distance) * (c.p - c.q);
        const std::array<double, 8> grad{{n.x * (1 - c.s), n.y * (1 - c.s), n.x * c.s, n.y * c.s,
                                          -n.x * (1 - c.t), -n.y * (1 - c.t), -n.x * c.t, -n.y * c.t}};
        const double h = 1e-6;
        for (int k = 0; k < 8; ++k)
          {
            auto plus = v;
            auto minus = v;
            plus[k] += h;
            minus[k] -= h;
            const double fd = (dist(plus) - dist(minus)) / (2 * h);
            EXPECT_NEAR(fd, grad[k], 1e-6 * std::max(1.0, std::abs(grad[k])))
                << "configuration " << checked << ", coordinate " << k;
          }
      }
  }

  // A random walk with unit steps kept inside a square box of side `box`;
  // nodes outside [first, first + n) are NaN so any access to them shows.
  std::vector<Vec2> random_wire(const unsigned int seed, const int first, const int n, const double box)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0.0, two_pi);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<Vec2> x(first + n + 3, Vec2{nan, nan});
    x[first] = {0.5 * box, 0.5 * box};
    for (int k = first + 1; k < first + n; ++k)
      for (;;)
        {
          const double a = angle(rng);
          const Vec2 y = x[k - 1] + Vec2{std::cos(a), std::sin(a)};
          if (y.x >= 0 && y.x <= box && y.y >= 0 && y.y <= box)
            {
              x[k] = y;
              break;
            }
        }
    return x;
  }

  bool is_sorted_unique(const std::vector<SegmentPair> &p)
  {
    for (std::size_t k = 1; k < p.size(); ++k)
      if (!(p[k - 1] < p[k]))
        return false;
    return true;
  }

  struct WireCase
  {
    unsigned int seed;
    int first;
    int n;
    int exclusion;
  };

  const std::vector<WireCase> wire_cases = {{1, 0, 200, 1},   {2, 7, 500, 2},   {3, 0, 1000, 3},
                                            {4, 50, 2000, 1}, {5, 13, 1500, 5}, {6, 1, 300, 10}};

  TEST(BroadPhase, MatchesBruteForceAfterRebuild)
  {
    const double diameter = 1.0, skin = 0.4;
    std::size_t total = 0;
    for (const auto &w : wire_cases)
      {
        const double box = std::sqrt(static_cast<double>(w.n)) * 0.8;
        const auto x = random_wire(w.seed, w.first, w.n, box);
        BroadPhase bp(diameter, skin, w.exclusion);
        EXPECT_TRUE(bp.update(x, w.first, w.first + w.n));
        EXPECT_EQ(bp.n_rebuilds(), 1u);
        const auto ref = BroadPhase::brute_force(x, w.first, w.first + w.n, diameter + skin, w.exclusion);
        EXPECT_FALSE(ref.empty());
        EXPECT_TRUE(is_sorted_unique(bp.candidates()));
        EXPECT_EQ(bp.candidates(), ref) << "seed " << w.seed;
        for (const auto &p : bp.candidates())
          EXPECT_GT(p.j - p.i, w.exclusion);
        total += ref.size();

        // Unchanged positions: no rebuild.
        EXPECT_FALSE(bp.update(x, w.first, w.first + w.n));
        EXPECT_EQ(bp.n_rebuilds(), 1u);
      }
    EXPECT_GT(total, 1000u);
  }

  TEST(BroadPhase, VerletSkinKeepsAllContacts)
  {
    const double diameter = 1.0, skin = 0.4;
    for (const auto &w : wire_cases)
      {
        const double box = std::sqrt(static_cast<double>(w.n)) * 0.8;
        const int last = w.first + w.n;
        const auto x0 = random_wire(w.seed, w.first, w.n, box);
        BroadPhase bp(diameter, skin, w.exclusion);
        ASSERT_TRUE(bp.update(x0, w.first, last));

        std::mt19937 rng(w.seed + 100);
        std::uniform_real_distribution<double> angle(0.0, two_pi);
        std::uniform_real_distribution<double> length(0.0, 0.499 * skin);
        for (int step = 0; step < 5; ++step)
          {
            auto x = x0;
            for (int k = w.first; k < last; ++k)
              {
                const double a = angle(rng);
                x[k] += length(rng) * Vec2{std::cos(a), std::sin(a)};
              }
            EXPECT_FALSE(bp.update(x, w.first, last));
            const auto touching = BroadPhase::brute_force(x, w.first, last, diameter, w.exclusion);
            EXPECT_TRUE(std::includes(bp.candidates().begin(), bp.candidates().end(), touching.begin(),
                                      touching.end()))
                << "seed " << w.seed << ", step " << step;
          }
        EXPECT_EQ(bp.n_rebuilds(), 1u);

        // One node beyond skin/2: rebuild, and the list is exact again.
        auto x = x0;
        x[w.first + w.n / 2] += Vec2{0.51 * skin, 0.0};
        EXPECT_TRUE(bp.update(x, w.first, last));
        EXPECT_EQ(bp.n_rebuilds(), 2u);
        EXPECT_EQ(bp.candidates(), BroadPhase::brute_force(x, w.first, last, diameter + skin, w.exclusion));
      }
  }

  TEST(BroadPhase, RebuildTriggers)
  {
    const int first = 3, n = 400;
    const auto x = random_wire(9, first, n, 16.0);
    BroadPhase bp(1.0, 0.3, 2);
    EXPECT_TRUE(bp.update(x, first, first + n));
    EXPECT_FALSE(bp.update(x, first, first + n));

    bp.invalidate();
    EXPECT_TRUE(bp.update(x, first, first + n));
    EXPECT_FALSE(bp.update(x, first, first + n));

    // Active range changes at either end.
    EXPECT_TRUE(bp.update(x, first + 1, first + n));
    EXPECT_EQ(bp.candidates(), BroadPhase::brute_force(x, first + 1, first + n, 1.3, 2));
    EXPECT_TRUE(bp.update(x, first + 1, first + n - 1));
    EXPECT_FALSE(bp.update(x, first + 1, first + n - 1));
    EXPECT_EQ(bp.n_rebuilds(), 4u);

    // Moving an inactive node never triggers a rebuild.
    auto y = x;
    y[first] += Vec2{5.0, 5.0};
    EXPECT_FALSE(bp.update(y, first + 1, first + n - 1));
  }

  TEST(BroadPhase, CoversWhatUpdateWouldKeep)
  {
    // covers() says, without rebuilding, whether update() would keep the
    // list: never before a build or for another range, and only while
    // every active node is within skin/2 of where the list was built.
    const int first = 3, n = 400, last = first + n;
    const double skin = 0.3;
    const auto x = random_wire(11, first, n, 16.0);
    BroadPhase bp(1.0, skin, 2);
    EXPECT_FALSE(bp.covers(x, first, last));
    ASSERT_TRUE(bp.update(x, first, last));
    EXPECT_TRUE(bp.covers(x, first, last));
    EXPECT_FALSE(bp.covers(x, first + 1, last));
    EXPECT_FALSE(bp.covers(x, first, last - 1));
    auto y = x;
    y[first + n / 2] += Vec2{0.0, 0.49 * skin};
    EXPECT_TRUE(bp.covers(y, first, last));
    y[first + n / 2] += Vec2{0.0, 0.02 * skin};
    EXPECT_FALSE(bp.covers(y, first, last));
    EXPECT_EQ(bp.n_rebuilds(), 1u); // covers() never rebuilds
    EXPECT_TRUE(bp.update(y, first, last));
    EXPECT_TRUE(bp.covers(y, first, last));
    bp.invalidate();
    EXPECT_FALSE(bp.covers(y, first, last));
  }

  TEST(BroadPhase, TooShortWires)
  {
    const auto x = random_wire(11, 2, 6, 3.0);
    BroadPhase bp(1.0, 0.3, 3);
    for (int last = 2; last <= 8; ++last)
      {
        bp.update(x, 2, last);
        EXPECT_EQ(bp.candidates(), BroadPhase::brute_force(x, 2, last, 1.3, 3));
      }
  }
} // namespace
