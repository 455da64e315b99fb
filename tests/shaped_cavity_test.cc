// Cavities other than the paper's circle and channels anywhere on the wall
// (scene::general_wall): channel placement, the initial wire's curve, the
// discrete wall term on any wall against the circle's closed form and
// against finite differences of its energy, the scene's checks, and runs of
// the discrete model to jamming.
#include <wirefem/discrete/terms.h>
#include <wirefem/injection/channel_placement.h>
#include <wirefem/injection/channels.h>
#include <wirefem/scene/cavity_setup.h>
#include <wirefem/scene/scene_reader.h>
#include <wirefem/simulation/simulation.h>
#include "force_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

namespace
{
  using namespace wirefem;
  using core::Vec2;
  using discrete::Chain;
  using discrete::StepEnergy;
  using injection::ChannelMouth;

  std::vector<ChannelMouth> mouths_on(const geometry::Cavity &wall, const double left, const double right,
                                      const double angle_degrees)
  {
    scene::InjectionParameters in;
    in.channel_positions = {left, right};
    in.channel_angle = angle_degrees;
    return scene::channel_mouths(wall, in);
  }

  TEST(ChannelPlacement, TheDefaultOnTheCircleIsThePapersMouth)
  {
    const double r = 7.0, hd = 0.5;
    const auto m = mouths_on(geometry::Cavity::circle(r), 0.5, 0.0, 0.0);
    const double corner_x = std::sqrt(r * r - hd * hd);
    EXPECT_NEAR(m[0].inlet.x, -r, 1e-12);
    EXPECT_NEAR(m[0].inlet.y, 0.0, 1e-12);
    EXPECT_NEAR(m[0].axis.x, 1.0, 1e-12);
    EXPECT_NEAR(m[1].axis.x, -1.0, 1e-12);
    for (const auto &mouth : m)
      for (const auto &c : mouth.corners)
        {
          EXPECT_NEAR(std::abs(c.x), corner_x, 1e-12);
          EXPECT_NEAR(std::abs(c.y), hd, 1e-12);
        }
  }

  TEST(ChannelPlacement, ObliqueCornersLieOnTheWallAndTheSideWalls)
  {
    const double q = std::sqrt(1.5);
    for (const auto &wall : {geometry::Cavity::circle(10.0), geometry::Cavity::ellipse(10.0 * q, 10.0 / q)})
      for (const double angle : {30.0, 60.0})
        for (const auto &m : mouths_on(wall, 0.4, 0.9, angle))
          {
            const auto w = wall.nearest(m.inlet);
            EXPECT_NEAR(w.depth, 0.0, 1e-9);
            // Turned clockwise from the inward normal by the angle.
            EXPECT_NEAR(core::dot(m.axis, w.normal), std::cos(angle * M_PI / 180.0), 1e-9);
            EXPECT_LT(core::cross(w.normal, m.axis), 0.0);
            for (int side = 0; side < 2; ++side)
              {
                EXPECT_NEAR(wall.nearest(m.corners[side]).depth, 0.0, 1e-9);
                EXPECT_NEAR(m.across(m.corners[side]), side == 0 ? 0.5 : -0.5, 1e-12);
                EXPECT_NEAR(m.along(m.corners[side]), m.corner_depth[side], 1e-12);
                // The channel walls end on the chord between the corners.
                EXPECT_NEAR(core::dot(m.corners[side] - m.cut_origin, m.cut_normal), 0.0, 1e-12);
              }
            EXPECT_NEAR(m.across(m.cut_origin), 0.0, 1e-12);
            EXPECT_GT(core::dot(m.cut_normal, m.axis), 0.0);
          }
  }

  TEST(ChannelPlacement, TheInitialCurveLeavesAndMeetsTheChannelsAlongTheirAxes)
  {
    const auto m = mouths_on(geometry::Cavity::circle(10.0), 0.5, 0.0, 45.0);
    const injection::InitialCurve curve(m[0], m[1]);
    const auto a = curve.at(0.0), b = curve.at(curve.length());
    EXPECT_NEAR(core::norm(a.position - m[0].inlet), 0.0, 1e-12);
    EXPECT_NEAR(core::norm(b.position - m[1].inlet), 0.0, 1e-12);
    // The normal is the tangent turned left: the tangent is axis_left at
    // the start and -axis_right at the end.
    EXPECT_NEAR(core::norm(a.normal - core::perp(m[0].axis)), 0.0, 1e-9);
    EXPECT_NEAR(core::norm(b.normal + core::perp(m[1].axis)), 0.0, 1e-9);
    // Arc length: equal steps along the curve have chords of that length
    // (to the curvature's second order).
    const int n = 2000;
    double chords = 0.0;
    for (int k = 0; k < n; ++k)
      chords += core::norm(curve.at(curve.length() * (k + 1) / n).position -
                           curve.at(curve.length() * k / n).position);
    EXPECT_NEAR(chords, curve.length(), 1e-6 * curve.length());
    EXPECT_GT(curve.length(), 20.0); // an S, longer than the diameter
    // The turning takes the tangent from the left axis to minus the right.
    const double start = std::atan2(m[0].axis.y, m[0].axis.x), end = std::atan2(-m[1].axis.y, -m[1].axis.x);
    EXPECT_NEAR(std::remainder(start + curve.turning() - end, 2.0 * M_PI), 0.0, 1e-9);
    EXPECT_LT(std::abs(curve.turning()), M_PI); // an S turns back
    // Facing channels: the straight line between the inlets.
    const auto f = mouths_on(geometry::Cavity::circle(10.0), 0.5, 0.0, 0.0);
    EXPECT_NEAR(injection::InitialCurve(f[0], f[1]).length(), 20.0, 1e-9);
  }

  TEST(ChannelPlacement, OneChannelStartsAStubToTheMiddleOfItsChord)
  {
    // The circle's radial channel: the chord is the diameter, the stub r.
    const double r = 10.0;
    scene::CavityParameters cavity;
    cavity.radius = r;
    scene::InjectionParameters in;
    in.channel_positions = {0.5};
    const auto wall = scene::channelled_wall(cavity, in);
    ASSERT_EQ(wall->mouths.size(), 1u);
    const auto &m = wall->mouths[0];
    EXPECT_NEAR(injection::free_end_length(wall->cavity, m), r, 1e-9);
    // Rounded to whole units: 10 / 3 rounds to 3 units of 3.
    EXPECT_NEAR(injection::initial_curve(*wall, 1.0).length(), 10.0, 1e-9);
    const auto stub = injection::initial_curve(*wall, 3.0);
    EXPECT_NEAR(stub.length(), 9.0, 1e-9);
    EXPECT_NEAR(core::norm(stub.at(9.0).position - (m.inlet + 9.0 * m.axis)), 0.0, 1e-9);
    EXPECT_NEAR(core::norm(stub.at(4.5).normal - core::perp(m.axis)), 0.0, 1e-12);
    EXPECT_NEAR(stub.turning(), 0.0, 1e-12);
    // The perturbation spans twice the stub, so the first mode peaks at its end.
    const auto shape = injection::initial_shape(3, 0.5, 1.0, stub, 1);
    const injection::InitialShape twice(3, 0.5, 18.0, 1.0);
    for (const double s : {1.0, 4.5, 9.0})
      EXPECT_EQ(shape.offset(s), twice.offset(s));
    // An ellipse of aspect 2 with the channel at its top, pointing down the
    // short axis: the stub is the half axis b = r / sqrt(2).
    cavity.shape = scene::CavityShape::ellipse;
    cavity.aspect_ratio = 2.0;
    in.channel_positions = {0.25};
    const auto ellipse = scene::channelled_wall(cavity, in);
    EXPECT_NEAR(ellipse->mouths[0].axis.y, -1.0, 1e-12);
    EXPECT_NEAR(injection::free_end_length(ellipse->cavity, ellipse->mouths[0]), r / std::sqrt(2.0), 1e-9);
    // One channel pushes: the wire inside grows by u(t), not 2 u(t).
    injection::Channels one(r, 0.1, 10.0), two(r, 0.1, 10.0);
    one.place(wall->mouths, 10.0, 0.0);
    two.place(scene::channel_mouths(wall->cavity, scene::InjectionParameters{}), 20.0, 0.0);
    EXPECT_EQ(one.count(), 1);
    EXPECT_FALSE(one.pushes(injection::Side::right));
    EXPECT_EQ(two.count(), 2);
    for (const double t : {3.0, 50.0})
      {
        EXPECT_DOUBLE_EQ(one.injected_length(t), 10.0 + one.injected_per_channel(t));
        EXPECT_DOUBLE_EQ(two.injected_length(t), 20.0 + 2.0 * two.injected_per_channel(t));
      }
  }

  discrete::ContactLaw stiff_law()
  {
    discrete::ContactLaw law;
    law.normal_stiffness = 2000.0;
    return law;
  }

  TEST(ShapedWall, OnTheCircleItIsTheCirclesClosedForm)
  {
    const double r = 5.0;
    const auto law = stiff_law();
    discrete::WallContactTerm circle(r, law);
    discrete::WallContactTerm shaped(r, law);
    const auto wall = geometry::Cavity::circle(r);
    shaped.use_shaped_wall(std::make_unique<discrete::ShapedWall>(wall, mouths_on(wall, 0.5, 0.0, 0.0)));
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Chain c(400);
    c.first = 0;
    c.last = 400;
    for (int k = 0; k < c.last; ++k)
      {
        // Inside the wall, most of them within d of it, some at the mouths.
        const double rho = r - 0.6 * std::abs(u(gen)), phi = M_PI * u(gen);
        c.x[k] = k % 10 == 0 ? Vec2{(k % 20 ? 1.0 : -1.0) * (r - 0.4 * std::abs(u(gen))), 0.6 * u(gen)}
                             : Vec2{rho * std::cos(phi), rho * std::sin(phi)};
      }
    Chain d = c;
    StepEnergy ec, ed;
    circle.add_forces(c, 1e-3, ec);
    shaped.add_forces(d, 1e-3, ed);
    ASSERT_GT(ec.n_wall_contacts, 50);
    EXPECT_EQ(ec.n_wall_contacts, ed.n_wall_contacts);
    EXPECT_NEAR(ec.contact, ed.contact, 1e-9 * ec.contact);
    for (int k = 0; k < c.last; ++k)
      EXPECT_NEAR(core::norm(c.f[k] - d.f[k]), 0.0, 1e-8) << "node " << k;
  }

  TEST(ShapedWall, ForcesAreTheGradientOfTheEnergyOnAnEllipseWithObliqueChannels)
  {
    const double q = std::sqrt(1.5), r = 6.0;
    const auto wall = geometry::Cavity::ellipse(r * q, r / q);
    const auto m = mouths_on(wall, 0.5, 0.0, 30.0);
    discrete::WallContactTerm term(r, stiff_law());
    term.use_shaped_wall(std::make_unique<discrete::ShapedWall>(wall, m));
    Chain c(10);
    c.first = 0;
    c.last = 8;
    const auto at_wall = [&](const double s, const double depth) {
      const auto w = wall.at(s * wall.perimeter());
      return w.point + depth * w.normal;
    };
    c.x[0] = at_wall(0.2, 0.3);                                                // pressed into the wall
    c.x[1] = at_wall(0.7, 0.45);                                               // just touching
    c.x[2] = m[0].corners[0] + 0.3 * m[0].axis - 0.05 * core::perp(m[0].axis); // in the mouth, at a corner
    c.x[3] = m[1].corners[1] + 0.2 * m[1].axis + 0.1 * core::perp(m[1].axis);  // the other mouth's corner
    c.x[4] = m[0].inlet - 1.0 * m[0].axis;                                     // in the channel: free
    c.x[5] =
        m[1].inlet - 0.2 * m[1].axis + 0.3 * core::perp(m[1].axis); // at the channel's side, near a corner
    c.x[6] = {0.5, 0.5};                                            // free
    c.x[7] = at_wall(0.33, -0.2);                                   // pushed through the wall
    test::expect_forces_match_energy(term, c, 1e-6);
    StepEnergy e;
    term.add_forces(c, 1e-3, e);
    EXPECT_EQ(c.f[4].x, 0.0);
    EXPECT_EQ(c.f[6].x, 0.0);
    EXPECT_GE(e.n_wall_contacts, 5);
  }
} // namespace
