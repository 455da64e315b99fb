// Analysis: the loop count of SPEC section 7 on hand-built wire shapes whose
// loops are known, with self-contacts found from the geometry.
#include <wirefem/analysis/observables.h>
#include <wirefem/analysis/shape_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace
{
  using namespace wirefem;
  using geometry::Vec2;

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

    analysis::WireState state(const bool with_contacts = true) const
    {
      analysis::WireState w;
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
} // namespace
