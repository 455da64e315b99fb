// Analysis: the loop count (docs/analysis.md) on hand-built wire shapes whose
// loops are known, with self-contacts found from the geometry.
#include <wirefem/analysis/observables.h>
#include <wirefem/analysis/shape_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

namespace
{
  using namespace wirefem;
  using core::Vec2;

  /// A centreline drawn with straight pieces and circular arcs, sampled at
  /// spacing <= h. Strands meant to touch run 0.9 d apart (contact < d).
  class Path
  {
  public:
    explicit Path(const Vec2 start) { p.push_back(start); }

    Path &line_to(const Vec2 q)
    {
      const Vec2 a = p.back();
      const int n = std::max(1, static_cast<int>(std::ceil(norm(q - a) / h)));
      for (int i = 1; i <= n; ++i)
        p.push_back(a + (static_cast<double>(i) / n) * (q - a));
      return *this;
    }

    /// Turns the current point about `centre` by `sweep` (radians, + = counterclockwise).
    Path &arc(const Vec2 centre, const double sweep)
    {
      const Vec2 a = p.back() - centre;
      const double radius = norm(a), start = std::atan2(a.y, a.x);
      const int n = std::max(1, static_cast<int>(std::ceil(radius * std::abs(sweep) / h)));
      for (int i = 1; i <= n; ++i)
        {
          const double t = start + sweep * i / n;
          p.push_back(centre + Vec2{radius * std::cos(t), radius * std::sin(t)});
        }
      return *this;
    }

    /// Turns about `centre` until the polar angle is `angle`, the short way
    /// in the given sense.
    Path &arc_to(const Vec2 centre, const double angle, const bool counterclockwise)
    {
      const Vec2 a = p.back() - centre;
      double sweep = angle - std::atan2(a.y, a.x);
      while (counterclockwise && sweep <= 0.0)
        sweep += 2.0 * M_PI;
      while (!counterclockwise && sweep >= 0.0)
        sweep -= 2.0 * M_PI;
      return arc(centre, sweep);
    }

    Vec2 last() const { return p.back(); }

    core::WireState state(const bool with_contacts = true) const
    {
      core::WireState w;
      w.points = p;
      w.arc_length.resize(p.size());
      for (std::size_t k = 1; k < p.size(); ++k)
        w.arc_length[k] = w.arc_length[k - 1] + norm(p[k] - p[k - 1]);
      if (with_contacts)
        w.self_contacts = analysis::find_self_contacts(w);
      return w;
    }

  private:
    std::vector<Vec2> p;
    double h = 0.2;
  };

  constexpr double half_gap = 0.45; // two touching strands lie 0.9 d apart

  /// A teardrop loop of radius `radius` standing up from the baseline y = 0
  /// at x0: up along x0 - 0.45, over the circle, down along x0 + 0.45.
  void teardrop_up(Path &path, const double x0, const double leg, const double radius)
  {
    const double c = std::sqrt(radius * radius - half_gap * half_gap);
    const Vec2 centre{x0, leg + c};
    path.line_to({x0 - half_gap, 0.0}).line_to({x0 - half_gap, leg});
    path.arc_to(centre, std::atan2(-c, half_gap), false);
    path.line_to({x0 + half_gap, 0.0});
  }

  /// Two legs 0.9 d apart, touching along their whole length, joined by a
  /// half circle of radius 0.45 d.
  Path zipped_hairpin()
  {
    Path path({-10.0, -half_gap});
    path.line_to({0.0, -half_gap}).arc({0.0, 0.0}, M_PI).line_to({-10.0, half_gap});
    return path;
  }

  TEST(Loops, StraightWireHasNone)
  {
    Path path({-10.0, 0.0});
    path.line_to({10.0, 0.0}).arc({10.0, 5.0}, 1.0);
    const auto w = path.state();
    EXPECT_TRUE(w.self_contacts.empty());
    EXPECT_EQ(analysis::count_loops(w), 0);
  }

  TEST(Loops, OneTeardrop)
  {
    Path path({-8.0, 0.0});
    teardrop_up(path, 0.0, 2.0, 3.0);
    path.line_to({8.0, 0.0});
    const auto w = path.state();
    ASSERT_FALSE(w.self_contacts.empty()) << "the legs must touch";
    EXPECT_EQ(analysis::count_loops(w), 1);
    // Without its contacts the same shape closes nothing.
    EXPECT_EQ(analysis::count_loops(path.state(false)), 0);
  }

  TEST(Loops, CascadeOfKLoops)
  {
    for (const int k : {2, 5})
      {
        Path path({-6.0, 0.0});
        for (int i = 0; i < k; ++i)
          teardrop_up(path, 9.0 * i, 1.5 + i, 3.0 - 0.3 * i);
        path.line_to({9.0 * k, 0.0});
        EXPECT_EQ(analysis::count_loops(path.state()), k) << k << " loops";
      }
  }

  TEST(Loops, LoopInsideALoopCountsTwice)
  {
    // A big teardrop with a smaller one hanging from its top into it: the
    // big face is bounded by one stretch (that runs round the small loop)
    // and one contact, the small loop by its own stretch and contact.
    const double radius = 7.0, c = std::sqrt(radius * radius - half_gap * half_gap);
    const Vec2 centre{0.0, 1.0 + c};
    Path path({-10.0, 0.0});
    path.line_to({-half_gap, 0.0}).line_to({-half_gap, 1.0});
    path.arc_to(centre, std::atan2(std::sqrt(radius * radius - 1.0), -1.0), false); // to x = -1 at the top
    const double top = path.last().y;
    path.line_to({-half_gap, top - 0.5}).line_to({-half_gap, top - 3.0});
    const double rs = 2.0, cs = std::sqrt(rs * rs - half_gap * half_gap);
    path.arc_to({0.0, top - 3.0 - cs}, std::atan2(cs, half_gap), true);
    path.line_to({half_gap, top - 0.5}).line_to({1.0, top});
    path.arc_to(centre, std::atan2(-c, half_gap), false);
    path.line_to({half_gap, 0.0}).line_to({10.0, 0.0});
    EXPECT_EQ(analysis::count_loops(path.state()), 2);
  }

  TEST(Loops, FigureOfEightSharingAStrand)
  {
    // Up along x = -0.45, over a circle, down along x = +0.45 past the
    // start, round a second circle below, up along x = 1.35: two loops
    // whose zipped necks share the middle strand.
    const double radius = 3.0, c = std::sqrt(radius * radius - half_gap * half_gap);
    Path path({-half_gap, -4.0});
    path.line_to({-half_gap, 0.0});
    path.arc_to({0.0, c}, std::atan2(-c, half_gap), false);
    path.line_to({half_gap, -6.0});
    path.arc_to({3.0 * half_gap - half_gap, -6.0 - c}, std::atan2(c, half_gap), true);
    path.line_to({3.0 * half_gap, -1.0}).line_to({10.0, -1.0});
    EXPECT_EQ(analysis::count_loops(path.state()), 2);
  }

  TEST(Loops, SpiralClosesOnlyItsInnermostTurn)
  {
    // Three touching turns of an Archimedean spiral (pitch 0.9 d): the
    // gaps between turns are bounded by two contacts each; only the disc
    // inside the first turn is a loop.
    Path path({2.0, 0.0});
    const double pitch = 2.0 * half_gap;
    double theta = 0.0;
    while (theta < 6.0 * M_PI)
      {
        const double r = 2.0 + pitch * theta / (2.0 * M_PI);
        theta += 0.2 / r;
        const double rn = 2.0 + pitch * theta / (2.0 * M_PI);
        path.line_to({rn * std::cos(theta), rn * std::sin(theta)});
      }
    const auto w = path.state();
    ASSERT_GT(w.self_contacts.size(), 50u);
    EXPECT_EQ(analysis::count_loops(w), 1);
  }

  TEST(Loops, ZippedHairpinIsOneLoop)
  {
    // Two legs touching along their whole length: the contacts cut the
    // space between them into slivers bounded by two contacts each; the
    // tip beyond the last contact is the one loop.
    const auto w = zipped_hairpin().state();
    ASSERT_GT(w.self_contacts.size(), 20u);
    EXPECT_EQ(analysis::count_loops(w), 1);
  }

  TEST(Loops, PlanarTracingAgreesWithTheArrangement)
  {
    // The face tracing of the planar graph against CGAL's arrangement with
    // exact constructions: on random cascades of teardrops and random
    // spirals (their contacts from the geometry fan out from each piece,
    // so chords cross) and on random smooth curves that also cross
    // themselves: both split at the crossings. The tracing must apply to
    // nearly all (it declines only for degenerate touching), and agree.
    std::vector<core::WireState> planar_shapes = {zipped_hairpin().state()};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 20; ++trial)
      {
        Path cascade({-6.0, 0.0});
        const int k = 1 + trial % 5;
        for (int i = 0; i < k; ++i)
          teardrop_up(cascade, 9.0 * i, 1.0 + 3.0 * u(rng), 1.5 + 2.5 * u(rng));
        cascade.line_to({9.0 * k, 0.0});
        planar_shapes.push_back(cascade.state());
        Path spiral({2.0, 0.0});
        const double pitch = 0.8 + 0.15 * u(rng), turns = 1.5 + 3.0 * u(rng);
        for (double theta = 0.0; theta < 2.0 * M_PI * turns;)
          {
            theta += 0.2 / (2.0 + pitch * theta / (2.0 * M_PI));
            const double r = 2.0 + pitch * theta / (2.0 * M_PI);
            spiral.line_to({r * std::cos(theta), r * std::sin(theta)});
          }
        planar_shapes.push_back(spiral.state());
      }
    int loops_seen = 0;
    for (const auto &w : planar_shapes)
      {
        const int planar = analysis::count_loops_planar(w);
        EXPECT_GE(planar, 0) << "a shape without degenerate touching was not traced";
        EXPECT_EQ(planar, analysis::count_loops_arrangement(w));
        loops_seen += planar;
      }
    EXPECT_GT(loops_seen, 40);
    int traced = 0, walk_loops = 0;
    for (int trial = 0; trial < 30; ++trial)
      {
        // A random smooth walk: heading driven by a random turning rate.
        Path walk({0.0, 0.0});
        Vec2 x{0.0, 0.0};
        double heading = 0.0, turning = 0.0;
        for (int step = 0; step < 400; ++step)
          {
            turning = 0.9 * turning + 0.25 * (u(rng) - 0.5);
            heading += turning;
            x = x + Vec2{0.2 * std::cos(heading), 0.2 * std::sin(heading)};
            walk.line_to(x);
          }
        const auto w = walk.state();
        const int planar = analysis::count_loops_planar(w);
        const int reference = analysis::count_loops_arrangement(w);
        if (planar >= 0)
          {
            ++traced;
            EXPECT_EQ(planar, reference) << "walk " << trial;
          }
        walk_loops += reference;
        EXPECT_EQ(analysis::count_loops(w), reference);
      }
    EXPECT_GE(traced, 27);
    EXPECT_GT(walk_loops, 10);
  }

  TEST(Loops, TouchingPiecesAndLongEdgesGoTheirOwnWays)
  {
    // A wire folded back exactly onto itself (collinear pieces overlapping)
    // is no planar straight-line graph: the tracing declines and count_loops
    // takes the arrangement's count. A cascade with one long diagonal tail
    // spreads over more grid cells than the pair finder allows itself: its
    // candidates come from the box tree, with the same count.
    Path folded({0.0, 0.0});
    folded.line_to({8.0, 0.0}).line_to({3.0, 0.0}).arc({3.0, 2.0}, -M_PI).line_to({8.0, 4.0});
    const auto f = folded.state();
    ASSERT_FALSE(f.self_contacts.empty());
    EXPECT_EQ(analysis::count_loops_planar(f), -1);
    EXPECT_EQ(analysis::count_loops(f), analysis::count_loops_arrangement(f));
    Path tail({-6.0, 0.0});
    for (int i = 0; i < 3; ++i)
      teardrop_up(tail, 9.0 * i, 1.5 + i, 3.0 - 0.3 * i);
    tail.line_to({27.0, 0.0});
    auto w = tail.state();
    w.points.push_back(w.points.back() + Vec2{3000.0, 3000.0});
    w.arc_length.push_back(w.arc_length.back() + 3000.0 * std::sqrt(2.0));
    const int planar = analysis::count_loops_planar(w);
    EXPECT_EQ(planar, 3);
    EXPECT_EQ(planar, analysis::count_loops_arrangement(w));
  }

  TEST(Loops, ContactsFromGeometryRespectTheExclusionLength)
  {
    // A tight bend (radius 0.45) brings points 1.4 d apart along the wire
    // within d of each other: within the exclusion length, no contact.
    const auto w = zipped_hairpin().state(false);
    for (const auto &c : analysis::find_self_contacts(w))
      {
        EXPECT_GT(c.s_b - c.s_a, 3.0);
        EXPECT_LT(norm(c.x_a - c.x_b), 1.0);
      }
  }

  std::string temporary_file(const std::string &name, const std::string &text)
  {
    const std::string file = ::testing::TempDir() + name;
    std::ofstream(file) << text;
    return file;
  }

  TEST(ShapeInput, CsvInMillimetresWithItsDiameterAndRadius)
  {
    // The teardrop in mm for a 0.8 mm wire in a cavity of radius 20 mm.
    Path path({-8.0, 0.0});
    teardrop_up(path, 0.0, 2.0, 3.0);
    path.line_to({8.0, 0.0});
    const auto w = path.state(false);
    std::string text = "# diameter = 0.8\n# radius = 20\nx,y\n";
    for (const auto &p : w.points)
      text += std::to_string(0.8 * p.x) + "," + std::to_string(0.8 * p.y) + "\n";
    const auto read = analysis::read_shape_csv(temporary_file("teardrop.csv", text), {});
    ASSERT_EQ(read.points.size(), w.points.size());
    EXPECT_NEAR(read.cavity_radius, 25.0, 1e-12);
    EXPECT_NEAR(read.injected_length, w.arc_length.back(), 1e-4);
    const std::string report = analysis::analysis_report(read, true);
    EXPECT_NE(report.find("\"loops\": 1"), std::string::npos) << report;
    EXPECT_NE(report.find("\"phi\": "), std::string::npos) << report;
    // Options override the file: a radius given on the command line wins.
    analysis::ShapeOptions o;
    o.cavity_radius = 40.0;
    EXPECT_NEAR(analysis::read_shape_csv(temporary_file("teardrop.csv", text), o).cavity_radius, 50.0, 1e-12);
  }

  TEST(ShapeInput, BadCsvNamesFileAndLine)
  {
    const auto file = temporary_file("bad.csv", "x,y\n0,0\n1,zero\n");
    try
      {
        analysis::read_shape_csv(file, {});
        FAIL() << "no error";
      }
    catch (const analysis::ShapeError &e)
      {
        EXPECT_NE(std::string(e.what()).find(file + ":3"), std::string::npos) << e.what();
      }
    EXPECT_THROW(analysis::read_shape_csv(temporary_file("one.csv", "0,0\n"), {}), analysis::ShapeError);
    EXPECT_THROW(analysis::read_shape(::testing::TempDir() + "no-such-file.csv", {}), analysis::ShapeError);
  }

  // Morphology (docs/analysis.md): the curvature ratio A/B of the paper's footnote, its
  // split into where the wire is and how curved it is there, the mirror
  // symmetry and the spiral's winding, on shapes whose values are known.

  /// A wire state with the given centreline and curvature, in a cavity of radius r.
  core::WireState shape(const std::vector<Vec2> &points, const std::vector<double> &curvature, const double r)
  {
    core::WireState w;
    w.cavity_radius = r;
    w.points = points;
    w.curvature = curvature;
    return w;
  }

  /// The straight wire across a cavity of radius 50 through its centre, one
  /// point per d (x = -50, ..., 50), curved `inside` within the inner disc of
  /// radius 50/sqrt(2) (x = -35..35: 71 points) and `outside` beyond it.
  core::WireState split_straight_wire(const double inside, const double outside)
  {
    const double r = 50.0;
    std::vector<Vec2> p;
    std::vector<double> kappa;
    for (int k = 0; k <= 100; ++k)
      {
        p.push_back({k - r, 0.0});
        kappa.push_back(std::abs(k - r) < r / std::sqrt(2.0) ? inside : outside);
      }
    return shape(p, kappa, r);
  }

  TEST(Morphology, CurvatureRatioOfTheEqualAreaDiscAndRing)
  {
    // Each point stands for the length d around it, the two end points for
    // none: 71 d inside, 28 d outside.
    const auto m = analysis::classify(split_straight_wire(0.1, 0.3));
    const double a = 0.01 * 71.0, b = 0.09 * 28.0;
    EXPECT_NEAR(m.curvature_ratio, a / b, 1e-12);
    EXPECT_EQ(m.phase, "classic"); // A/B = 0.28 < 0.5
    EXPECT_NEAR(m.inner_wire_fraction, 71.0 / 99.0, 1e-12);
    EXPECT_NEAR(m.curvature_density_ratio, 0.01 / 0.09, 1e-12);
    const double f = m.inner_wire_fraction;
    EXPECT_NEAR(m.curvature_ratio, f / (1.0 - f) * m.curvature_density_ratio, 1e-12);

    const auto swapped = analysis::classify(split_straight_wire(0.3, 0.1));
    EXPECT_NEAR(swapped.curvature_ratio, 0.09 * 71.0 / (0.01 * 28.0), 1e-9);
    EXPECT_EQ(swapped.phase, "plastic");
    // Evenly curved, A/B is the ratio of the lengths alone.
    const auto even = analysis::classify(split_straight_wire(0.2, 0.2));
    EXPECT_NEAR(even.curvature_ratio, 71.0 / 28.0, 1e-12);
    EXPECT_NEAR(even.curvature_density_ratio, 1.0, 1e-12);
    // No curvature outside: A/B is unbounded; none at all: 0.
    EXPECT_TRUE(std::isinf(analysis::classify(split_straight_wire(0.2, 0.0)).curvature_ratio));
    EXPECT_EQ(analysis::classify(split_straight_wire(0.0, 0.0)).curvature_ratio, 0.0);
  }

  TEST(Morphology, MirrorSymmetryScore)
  {
    // y = h cos(pi x / 2r) is mirror-symmetric about the y axis: score 1.
    // y = h sin(pi x / r) is point-symmetric: the mirrored left half lies 2|y|
    // from the right half, a mean of 4h/pi, so the score is 1 - 4h/(pi r).
    const double r = 50.0, h = 2.0;
    std::vector<Vec2> even, odd;
    for (int k = 0; k <= 100; ++k)
      {
        const double x = k - r;
        even.push_back({x, h * std::cos(M_PI * x / (2.0 * r))});
        odd.push_back({x, h * std::sin(M_PI * x / r)});
      }
    const std::vector<double> none(101, 0.0);
    EXPECT_NEAR(analysis::classify(shape(even, none, r)).symmetry, 1.0, 1e-12);
    EXPECT_NEAR(analysis::classify(shape(odd, none, r)).symmetry, 1.0 - 4.0 * h / (M_PI * r), 1e-3);
    // Displaced by a diameter, the halves lie farther apart than r: score 0 (clamped).
    std::vector<Vec2> far = even;
    for (std::size_t k = 51; k < far.size(); ++k)
      far[k].y += 2.0 * r;
    EXPECT_EQ(analysis::classify(shape(far, none, r)).symmetry, 0.0);
  }

  /// The circle of radius r as a wall polygon with one channel at (-r, 0)
  /// pointing +x, and no wire yet.
  core::WireState one_channel_circle(const double r)
  {
    core::WireState w;
    w.cavity_radius = r;
    for (int k = 0; k < 64; ++k)
      w.wall.push_back({r * std::cos(2.0 * M_PI * k / 64), r * std::sin(2.0 * M_PI * k / 64)});
    w.channels = {{{-r, 0.0}, {1.0, 0.0}}};
    return w;
  }

  TEST(Morphology, OneChannelMirrorSymmetryIsTheShareOfTheWireItsImageCovers)
  {
    // One channel at (-r, 0) pointing +x in the circle: the mirror line is
    // the x axis. A wire along it is its own image (1). Half along it and
    // half straight up from (-5, 0): the upper half's image lies 1 d or
    // more below the wire, so half the points are covered (6 of 12).
    const double r = 10.0;
    auto w = one_channel_circle(r);
    for (int k = 0; k <= 10; ++k)
      w.points.push_back({k - r, 0.0});
    w.curvature.assign(w.points.size(), 0.0);
    EXPECT_DOUBLE_EQ(analysis::classify(w).symmetry, 1.0);
    w.points.clear();
    for (int k = 0; k < 6; ++k)
      w.points.push_back({k - r, 0.0});
    for (int k = 1; k <= 6; ++k)
      w.points.push_back({-5.0, double(k)});
    w.curvature.assign(w.points.size(), 0.0);
    EXPECT_DOUBLE_EQ(analysis::classify(w).symmetry, 0.5);
    // Shifted 0.3 d across the line, the straight wire's image misses it
    // by 0.6 d: nothing covered.
    for (auto &p : w.points)
      p = {p.x, 0.3};
    EXPECT_DOUBLE_EQ(analysis::classify(w).symmetry, 0.0);
  }

  TEST(Morphology, OneChannelsCoilIsASpiral)
  {
    // A coil wound from the channel at (-r, 0), three turns inwards to the
    // free end: each half, followed from its end, turns 1.5 times, the
    // halves opposite ways.
    const double r = 10.0;
    auto w = one_channel_circle(r);
    for (int k = 0; k <= 300; ++k)
      {
        const double turn = 3.0 * k / 300.0, rho = 9.5 - 2.0 * turn;
        w.points.push_back({-rho * std::cos(2.0 * M_PI * turn), -rho * std::sin(2.0 * M_PI * turn)});
      }
    w.curvature.assign(w.points.size(), 0.0);
    const auto m = analysis::classify(w);
    EXPECT_NEAR(m.winding_left, 1.5, 0.01); // counter-clockwise
    EXPECT_NEAR(m.winding_right, -1.5, 0.01);
    EXPECT_EQ(m.phase, "spiral");
    // Folded: the same coil inwards for half the wire, then back out
    // between its turns to the free end at the wall: a double spiral.
    const auto coil = w.points;
    w.points.assign(coil.begin(), coil.begin() + 151);
    for (int k = 149; k >= 0; --k)
      w.points.push_back(0.95 * coil[k]);
    w.curvature.assign(w.points.size(), 0.0);
    const auto folded = analysis::classify(w);
    EXPECT_GT(folded.winding_left, 0.75);
    EXPECT_GT(folded.winding_right, 0.75);
    EXPECT_EQ(folded.phase, "spiral");
    // Folded, the halves net no winding between them, but the wire is still
    // coiled from end to end.
    EXPECT_GT(folded.coiled_fraction, 0.95);
  }

  TEST(Morphology, SpiralWhenMostOfTheWireWindsWithoutTurningBack)
  {
    // Each half winds 1.5 turns clockwise inwards from its inlet, and the
    // two meet on a straight piece through the centre (mid-wire): a double
    // spiral, symmetric under a half turn, coiled from end to end.
    const double r = 50.0, turns = 1.5;
    const int n_arm = 600, n_join = 10;
    const auto arm = [&](const int i, const double start_angle, const double scale = 1.0) {
      const double t = static_cast<double>(i) / n_arm;
      const double rho = scale * r * (1.0 - 0.9 * t), theta = start_angle - 2.0 * M_PI * turns * t;
      return Vec2{rho * std::cos(theta), rho * std::sin(theta)};
    };
    const auto classify = [&](const std::vector<Vec2> &p) {
      return analysis::classify(shape(p, std::vector<double>(p.size(), 0.02), r));
    };
    std::vector<Vec2> p;
    for (int i = 0; i <= n_arm; ++i)
      p.push_back(arm(i, M_PI));
    // From (0.1 r, 0) through the centre to (-0.1 r, 0), the centre at mid-wire.
    for (int i = 1; i < 2 * n_join; ++i)
      p.push_back({0.1 * r * (1.0 - static_cast<double>(i) / n_join), 0.0});
    for (int i = n_arm; i >= 0; --i)
      p.push_back(arm(i, 0.0));
    ASSERT_EQ(p.size() % 2, 1u);
    EXPECT_EQ(norm(p[p.size() / 2]), 0.0);
    auto m = classify(p);
    EXPECT_NEAR(m.winding_left, -turns, 1e-9);
    EXPECT_NEAR(m.winding_right, -turns, 1e-9);
    EXPECT_NEAR(m.coiled_fraction, 1.0, 1e-12);
    EXPECT_EQ(m.phase, "spiral");

    // Folded: each half winds in and back out between its own turns, so it
    // nets little winding (the old test, 0.75 net turns per half, missed
    // such a wire), yet the wire is coiled from end to end.
    p.clear();
    for (int i = 0; i <= n_arm; ++i)
      p.push_back(arm(i, M_PI));
    for (int i = n_arm; i >= 0; --i)
      p.push_back(arm(i, M_PI, 0.95));
    for (int i = 0; i <= n_arm; ++i)
      p.push_back(arm(i, 0.0, 0.95));
    for (int i = n_arm; i >= 0; --i)
      p.push_back(arm(i, 0.0));
    m = classify(p);
    EXPECT_LT(std::abs(m.winding_left), 0.75);
    EXPECT_LT(std::abs(m.winding_right), 0.75);
    EXPECT_GT(m.coiled_fraction, 0.99);
    EXPECT_EQ(m.phase, "spiral");

    // A large loop round the centre that turns back on itself again and
    // again: each half, from its inlet, advances 0.9 turns clockwise while
    // swinging +-0.4 rad ten times. By net winding (0.75 turns per half,
    // the same way) that was a spiral, but no stretch winds a full turn.
    // The halves' ends, half a turn apart, are joined through the centre.
    const auto swinging = [&](const double start) {
      std::vector<Vec2> q;
      for (int i = 0; i <= 2000; ++i)
        {
          const double t = i / 2000.0;
          const double theta = start - 2.0 * M_PI * 0.9 * t + 0.4 * std::sin(2.0 * M_PI * 10.0 * t);
          const double rho = r * (0.6 + 0.3 * std::cos(2.0 * M_PI * 10.0 * t));
          q.push_back({rho * std::cos(theta), rho * std::sin(theta)});
        }
      return q;
    };
    p = swinging(M_PI);
    const auto from_right = swinging(0.0);
    // Joined straight through the centre, which is mid-wire.
    const Vec2 left_end = p.back(), right_end = from_right.back();
    for (int i = 1; i <= n_join; ++i)
      p.push_back((1.0 - static_cast<double>(i) / n_join) * left_end);
    for (int i = 1; i < n_join; ++i)
      p.push_back((static_cast<double>(i) / n_join) * right_end);
    p.insert(p.end(), from_right.rbegin(), from_right.rend());
    ASSERT_EQ(norm(p[p.size() / 2]), 0.0);
    m = classify(p);
    EXPECT_NEAR(m.winding_left, -0.9, 0.01);
    EXPECT_NEAR(m.winding_right, -0.9, 0.01);
    EXPECT_EQ(m.coiled_fraction, 0.0);
    EXPECT_NE(m.phase, "spiral");

    // A spiral along the wall that gives way to loops: each half follows
    // the wall 1.2 turns, then folds back and forth across a quarter of
    // the cavity for twice that length. Each half winds more than a turn,
    // but only a third of the wire is coiled: not a spiral.
    p.clear();
    const double rim = 0.95 * r, rim_turns = 1.2, rim_length = 2.0 * M_PI * rim * rim_turns;
    const auto half = [&](const double start, const double sense) {
      std::vector<Vec2> q;
      const int n_rim = 400;
      for (int i = 0; i <= n_rim; ++i)
        {
          const double theta = start - sense * 2.0 * M_PI * rim_turns * i / n_rim;
          q.push_back({rim * std::cos(theta), rim * std::sin(theta)});
        }
      // Folds across the cavity, from 0.8 r at the rim's last angle to
      // 0.2 r a third of a radian further on and back: the polar angle
      // turns back at every fold.
      const double end = start - sense * 2.0 * M_PI * rim_turns;
      double folded_length = 0.0;
      for (int k = 0; folded_length < 2.0 * rim_length; ++k)
        for (int i = 1; i <= 20; ++i)
          {
            const double u = k % 2 ? 1.0 - i / 20.0 : i / 20.0;
            const double theta = end - sense * u / 3.0, rho = r * (0.8 - 0.6 * u);
            folded_length += norm(Vec2{rho * std::cos(theta), rho * std::sin(theta)} - q.back());
            q.push_back({rho * std::cos(theta), rho * std::sin(theta)});
          }
      return q;
    };
    p = half(M_PI, 1.0);
    auto right = half(0.0, 1.0);
    p.insert(p.end(), right.rbegin(), right.rend());
    m = classify(p);
    EXPECT_LT(m.winding_left, -1.0);
    EXPECT_LT(m.winding_right, -1.0);
    EXPECT_GT(m.coiled_fraction, 0.25);
    EXPECT_LT(m.coiled_fraction, 0.4);
    EXPECT_NE(m.phase, "spiral");
  }
} // namespace
