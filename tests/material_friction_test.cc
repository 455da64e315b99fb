// The elastoplastic moment-curvature law and the friction law, each alone.
#include <wirefem/contact/friction_law.h>
#include <wirefem/material/moment_curvature_law.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace
{
  using wirefem::material::Hardening;
  using wirefem::material::MomentCurvatureLaw;
  using wirefem::material::PlasticState;

  constexpr double c = 60.0;  // stiffness k2
  constexpr double ey = 0.04; // yield strain
  constexpr double s = 0.08;  // hardening slope

  // Drives the law along a strain path in small increments; returns the
  // moments and accumulates the plastic work.
  struct Path
  {
    std::vector<double> moment;
    double plastic_work = 0.0;
    PlasticState state;
  };
  Path drive(const MomentCurvatureLaw &law, const std::vector<double> &targets, const int n_per_leg = 2000)
  {
    Path p;
    double e = 0.0;
    for (const double target : targets)
      {
        const double start = e;
        for (int i = 1; i <= n_per_leg; ++i)
          {
            e = start + (target - start) * i / n_per_leg;
            const auto r = law.evaluate(e, p.state);
            p.state = r.state;
            p.plastic_work += r.plastic_work;
            p.moment.push_back(r.moment);
          }
      }
    return p;
  }

  TEST(MomentCurvatureLaw, ElasticBelowYieldThenHardeningSlope)
  {
    const MomentCurvatureLaw law(c, ey, s, Hardening::kinematic);
    const auto below = law.evaluate(0.5 * ey, {});
    EXPECT_DOUBLE_EQ(below.moment, c * 0.5 * ey);
    EXPECT_DOUBLE_EQ(below.tangent, c);
    EXPECT_DOUBLE_EQ(below.state.plastic_strain, 0.0);
    // One big step past yield: the return is exact for linear hardening.
    const double e = 3.0 * ey;
    const auto r = law.evaluate(e, {});
    EXPECT_NEAR(r.moment, c * ey + s * c * (e - ey), 1e-12);
    EXPECT_NEAR(r.tangent, s * c, 1e-12);
    EXPECT_GT(r.state.plastic_strain, 0.0);
  }

  TEST(MomentCurvatureLaw, TangentMatchesFiniteDifferenceOfMoment)
  {
    for (const auto h : {Hardening::kinematic, Hardening::isotropic})
      {
        const MomentCurvatureLaw law(c, ey, s, h);
        PlasticState old;
        old.plastic_strain = 0.03;
        old.accumulated_strain = 0.05;
        for (const double e : {-0.2, -0.05, 0.0, 0.05, 0.08, 0.2})
          {
            const double d = 1e-7;
            const double fd = (law.evaluate(e + d, old).moment - law.evaluate(e - d, old).moment) / (2 * d);
            EXPECT_NEAR(law.evaluate(e, old).tangent, fd, 1e-5 * c) << "strain " << e;
          }
      }
  }

  TEST(MomentCurvatureLaw, UnloadingIsElasticAndReverseYieldIsKinematic)
  {
    const MomentCurvatureLaw law(c, ey, s, Hardening::kinematic);
    const double ea = 0.2;
    const auto load = law.evaluate(ea, {});
    // Unload by less than the elastic range 2 e_y: slope c, no new flow.
    const auto unload = law.evaluate(ea - 1.5 * ey, load.state);
    EXPECT_NEAR(unload.moment, load.moment - c * 1.5 * ey, 1e-12);
    EXPECT_DOUBLE_EQ(unload.state.plastic_strain, load.state.plastic_strain);
    // The elastic range has width 2 M_y around the back moment H e_p.
    const double H = s * c / (1 - s);
    const auto just_inside = law.evaluate(ea - 1.999 * ey, load.state);
    EXPECT_DOUBLE_EQ(just_inside.state.plastic_strain, load.state.plastic_strain);
    const auto beyond = law.evaluate(ea - 2.5 * ey, load.state);
    EXPECT_LT(beyond.state.plastic_strain, load.state.plastic_strain);
    const double back = H * beyond.state.plastic_strain; // after the return
    EXPECT_NEAR(beyond.moment - back, -c * ey, 1e-9 * c) << "on the reverse yield surface";
  }

  TEST(MomentCurvatureLaw, IsotropicHardeningGrowsTheElasticRange)
  {
    const MomentCurvatureLaw law(c, ey, s, Hardening::isotropic);
    const double H = s * c / (1 - s);
    const auto load = law.evaluate(0.2, {});
    const double radius = c * ey + H * load.state.accumulated_strain;
    EXPECT_NEAR(load.moment, radius, 1e-9);
    // Reverse yield only once M reaches -radius (no back moment).
    const auto rev = law.evaluate(0.2 - 2.5 * ey - radius / c, load.state);
    EXPECT_LT(rev.state.plastic_strain, load.state.plastic_strain);
    EXPECT_NEAR(rev.moment, -(c * ey + H * rev.state.accumulated_strain), 1e-9);
  }

  TEST(MomentCurvatureLaw, CycleDissipationMatchesClosedForm)
  {
    // Strain cycles between +-e_a after first loading: the stabilised
    // kinematic loop is a parallelogram of area 4 c e_y (1 - s)(e_a - e_y).
    const MomentCurvatureLaw law(c, ey, s, Hardening::kinematic);
    const double ea = 0.3;
    const auto first = drive(law, {ea});
    Path cycle;
    cycle.state = first.state;
    const auto p = [&] {
      Path q = cycle;
      double e = ea, work = 0.0;
      for (const double target : {-ea, ea})
        {
          const double start = e;
          for (int i = 1; i <= 20000; ++i)
            {
              e = start + (target - start) * i / 20000;
              const auto r = law.evaluate(e, q.state);
              q.state = r.state;
              work += r.plastic_work;
            }
        }
      q.plastic_work = work;
      return q;
    }();
    const double closed_form = 4.0 * c * ey * (1 - s) * (ea - ey);
    EXPECT_NEAR(p.plastic_work, closed_form, 1e-3 * closed_form);
    // The loop closes: back at +e_a with the same plastic strain.
    EXPECT_NEAR(p.state.plastic_strain, first.state.plastic_strain, 1e-12);
  }

  TEST(MomentCurvatureLaw, SlopeOneAndHugeYieldAreElastic)
  {
    const MomentCurvatureLaw hard(c, ey, 1.0, Hardening::kinematic);
    EXPECT_FALSE(hard.is_plastic());
    EXPECT_DOUBLE_EQ(hard.evaluate(1.0, {}).moment, c);
    const MomentCurvatureLaw neutral(c, M_PI, s, Hardening::kinematic);
    const MomentCurvatureLaw elastic(c);
    for (const double e : {-3.1, -1.0, 0.5, 3.14})
      EXPECT_EQ(neutral.evaluate(e, {}).moment, elastic.evaluate(e, {}).moment);
  }

  using wirefem::contact::friction_update;
  using wirefem::contact::FrictionCoefficients;
  using wirefem::contact::FrictionHistory;

  FrictionCoefficients coefficients()
  {
    FrictionCoefficients f;
    f.mu_static = 0.6;
    f.mu_dynamic = 0.4;
    f.threshold_velocity = 0.01;
    f.tangential_stiffness = 100.0;
    return f;
  }

  TEST(FrictionLaw, SticksBelowTheStaticLimit)
  {
    const auto f = coefficients();
    FrictionHistory h;
    const double fn = 10.0, v = 0.1, dt = 0.01;
    // 5 steps: u = 0.005, force 0.5 < 6.
    FrictionHistory cur = h;
    double force = 0.0;
    for (int i = 0; i < 5; ++i)
      {
        const auto r = friction_update(f, fn, v, dt, cur);
        cur = r.history;
        force = r.force;
      }
    EXPECT_FALSE(cur.sliding);
    EXPECT_NEAR(force, -f.tangential_stiffness * 5 * v * dt, 1e-12);
  }

  TEST(FrictionLaw, SlipsAtTheStaticLimitWithDynamicForceAndResticks)
  {
    const auto f = coefficients();
    const double fn = 10.0, dt = 0.01;
    FrictionHistory h;
    double max_stick_force = 0.0;
    int steps = 0;
    // Push at constant speed until it slides.
    while (!h.sliding && steps < 10000)
      {
        const auto r = friction_update(f, fn, 0.5, dt, h);
        if (!r.history.sliding)
          max_stick_force = std::max(max_stick_force, std::abs(r.force));
        else
          EXPECT_NEAR(r.force, -f.mu_dynamic * fn, 1e-12);
        h = r.history;
        ++steps;
      }
    ASSERT_TRUE(h.sliding);
    EXPECT_LE(max_stick_force, f.mu_static * fn + 1e-12);
    EXPECT_GT(max_stick_force, f.mu_static * fn - f.tangential_stiffness * 0.5 * dt - 1e-12);
    // Sliding on: the dynamic force against the motion, in either direction.
    auto r = friction_update(f, fn, 0.5, dt, h);
    EXPECT_TRUE(r.history.sliding);
    EXPECT_NEAR(r.force, -f.mu_dynamic * fn, 1e-12);
    // Below the threshold velocity it sticks again, from the spring at the
    // dynamic force, and the static limit applies again.
    r = friction_update(f, fn, 0.5 * f.threshold_velocity, dt, r.history);
    EXPECT_FALSE(r.history.sliding);
    EXPECT_LT(std::abs(r.force), f.mu_static * fn);
  }

  TEST(FrictionLaw, DissipationIsWorkTakenMinusStoredEnergy)
  {
    const auto f = coefficients();
    const double dt = 0.01;
    FrictionHistory h;
    double dissipated = 0.0, work = 0.0, previous_force = 0.0;
    for (int i = 0; i < 3000; ++i)
      {
        const double v = std::sin(0.01 * i) * 0.8;
        const double fn = 5.0 + 4.0 * std::cos(0.003 * i);
        // Over the displacement v dt of this update the force went from the
        // previous one to the new one: trapezoidal rule, as the
        // central-difference scheme's kinetic energy sees it.
        const auto r = friction_update(f, fn, v, dt, h);
        work += -0.5 * (previous_force + r.force) * v * dt;
        dissipated += r.dissipated;
        previous_force = r.force;
        h = r.history;
      }
    const double stored = 0.5 * f.tangential_stiffness * h.elongation * h.elongation;
    EXPECT_NEAR(dissipated + stored, work, 1e-9 * std::abs(work));
    EXPECT_GT(dissipated, 0.0);
  }

  TEST(FrictionLaw, StickingContactDissipatesNothing)
  {
    // A node of mass m held by a sticking contact oscillates on the
    // tangential spring, integrated by the central-difference scheme of the
    // discrete model. The scheme conserves 1/2 m v_{n-1/2} v_{n+1/2} +
    // 1/2 k_t u_n^2 exactly, so a sticking contact must report zero
    // dissipation, at any step (a one-sided rule reports -k_t (v dt)^2 / 2
    // per step, a drift that grows with every step of a jammed packing).
    auto f = coefficients();
    f.mu_static = 1e6; // never slips
    const double m = 0.7, dt = 0.2 * std::sqrt(m / f.tangential_stiffness);
    FrictionHistory h;
    double v = 0.3, dissipated = 0.0, largest = 0.0;
    for (int i = 0; i < 2000; ++i)
      {
        const auto r = friction_update(f, 1.0, v, dt, h);
        dissipated += r.dissipated;
        largest = std::max(largest, std::abs(r.force * v * dt));
        v += dt * r.force / m;
        h = r.history;
      }
    EXPECT_FALSE(h.sliding);
    EXPECT_LT(std::abs(dissipated), 1e-10 * largest) << "largest work per step " << largest;
  }

  TEST(FrictionLaw, ZeroCoefficientGivesZeroForce)
  {
    auto f = coefficients();
    f.mu_static = f.mu_dynamic = 0.0;
    FrictionHistory h;
    for (const double v : {0.3, -0.2, 0.0, 1e-4})
      {
        const auto r = friction_update(f, 3.0, v, 0.01, h);
        EXPECT_EQ(r.force, 0.0);
        h = r.history;
      }
  }
} // namespace
