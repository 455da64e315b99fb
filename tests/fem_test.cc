// The rod FEM: element residual against finite differences of its energy,
// tangents against finite differences of the residual (with and without
// plasticity, viscosity and contact), rigid-body rotation, locking at
// slenderness 1e4, friction stick and slip, Newton convergence and the
// energy balance of a small run.
#include <wirefem/contact/friction_law.h>
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>
#include <wirefem/fem/rod_model.h>
#include "resume_check.h"
#include "rod_probe.h"
#include <wirefem/simulation/capstan.h>
#include <wirefem/injection/channels.h>
#include <wirefem/scene/cavity_setup.h>
#include <wirefem/scene/scene_reader.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <vector>

namespace
{
  using namespace wirefem;
  using core::Vec2;

  material::MomentCurvatureLaw plastic_law(double yield = 0.01)
  {
    return material::MomentCurvatureLaw(60.0, yield, 0.1, scene::Hardening::kinematic);
  }

  fem::SectionProperties section(double eta_a = 0.0, double eta_b = 0.0)
  {
    fem::SectionProperties s;
    s.EA = 1000.0;
    s.GA = 346.0;
    s.axial_viscosity = eta_a;
    s.bending_viscosity = eta_b;
    return s;
  }

  // A curved, stretched element: x = S + noise, y and theta small waves.
  std::vector<double> random_dofs(const fem::ElementShape &shape, std::mt19937 &gen, double amp = 0.05)
  {
    std::uniform_real_distribution<double> u(-amp, amp);
    std::vector<double> d(3 * shape.n_nodes);
    for (unsigned int a = 0; a < shape.n_nodes; ++a)
      {
        d[3 * a] = shape.node_position[a] * shape.length + u(gen);
        d[3 * a + 1] = u(gen);
        d[3 * a + 2] = 3.0 * u(gen);
      }
    return d;
  }

  std::vector<fem::PointState> random_states(unsigned int n, std::mt19937 &gen)
  {
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    std::vector<fem::PointState> s(n);
    for (auto &p : s)
      {
        p.plastic.plastic_strain = u(gen);
        p.axial_strain = 0.1 * u(gen);
        p.curvature = u(gen);
      }
    return s;
  }

  TEST(RodElement, ResidualIsTheGradientOfTheEnergy)
  {
    std::mt19937 gen(3);
    // Elastic range with a non-zero plastic strain: yield far away.
    const auto law = plastic_law(10.0);
    for (unsigned int p = 1; p <= 3; ++p)
      for (const unsigned int nq : {p, p + 1})
        {
          const auto shape = fem::ElementShape::lagrange(p, 1.3, nq);
          const auto dofs = random_dofs(shape, gen);
          const auto old = random_states(nq, gen);
          fem::ElementResult r;
          fem::evaluate_rod_element(shape, section(), law, dofs.data(), old.data(), 0.0, false, r);
          double worst = 0, scale = 0;
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const double h = 1e-6;
              auto plus = dofs, minus = dofs;
              plus[i] += h;
              minus[i] -= h;
              const double fd = (fem::rod_element_energy(shape, section(), law, plus.data(), old.data()) -
                                 fem::rod_element_energy(shape, section(), law, minus.data(), old.data())) /
                                (2 * h);
              worst = std::max(worst, std::abs(fd - r.residual[i]));
              scale = std::max(scale, std::abs(r.residual[i]));
            }
          EXPECT_GT(scale, 1.0) << "degenerate test state";
          EXPECT_LT(worst, 1e-6 * scale) << "p = " << p << ", n_q = " << nq;
        }
  }

  void expect_tangent_matches_residual(const fem::ElementShape &shape,
                                       const material::MomentCurvatureLaw &law,
                                       const fem::SectionProperties &sec, const double dt,
                                       const std::vector<double> &dofs,
                                       const std::vector<fem::PointState> &old)
  {
    fem::ElementResult r, rp, rm;
    fem::evaluate_rod_element(shape, sec, law, dofs.data(), old.data(), dt, true, r);
    const unsigned int n = dofs.size();
    double worst = 0, scale = 0;
    for (unsigned int j = 0; j < n; ++j)
      {
        const double h = 1e-7;
        auto plus = dofs, minus = dofs;
        plus[j] += h;
        minus[j] -= h;
        fem::evaluate_rod_element(shape, sec, law, plus.data(), old.data(), dt, false, rp);
        fem::evaluate_rod_element(shape, sec, law, minus.data(), old.data(), dt, false, rm);
        for (unsigned int i = 0; i < n; ++i)
          {
            const double fd = (rp.residual[i] - rm.residual[i]) / (2 * h);
            worst = std::max(worst, std::abs(fd - r.tangent[i * n + j]));
            scale = std::max(scale, std::abs(r.tangent[i * n + j]));
          }
      }
    EXPECT_LT(worst, 1e-6 * scale) << "degree " << shape.n_nodes - 1;
  }

  // The channel walls on one element: gradient against finite differences
  // of the energy, and the tangent against finite differences of the
  // gradient, for degrees 1 and 2, crossing the mouth either way and wholly
  // inside (where the tangent is exact), with the mouth across the axis or
  // aslant; the closed form inside for degree 1.
  TEST(ChannelWall, GradientIsTheDerivativeOfTheEnergy)
  {
    const double k = 2000.0, h = 1.0;
    const Vec2 axis{1.0, 0.0};
    struct Case
    {
      std::vector<double> pos;
      std::vector<double> X;
    };
    const std::vector<Case> cases = {
        {{0.0, 1.0}, {-0.6, 0.03, 0.35, -0.2}},                   // p = 1, leaving the channel
        {{0.0, 1.0}, {0.4, 0.25, -0.55, 0.04}},                   // p = 1, the other way round
        {{0.0, 1.0}, {-2.0, 0.05, -1.0, -0.07}},                  // p = 1, inside
        {{0.0, 1.0, 0.5}, {-0.7, 0.02, 0.3, 0.3, -0.2, -0.04}},   // p = 2, curved across the mouth
        {{0.0, 1.0, 0.5}, {0.45, -0.3, -0.6, 0.05, -0.05, -0.1}}, // p = 2, the other way round
    };
    // The paper's mouth (s along the axis), and a mouth cut aslant (s
    // along the normal of a chord 20 degrees off, y across the axis).
    const Vec2 aslant{std::cos(0.35), std::sin(0.35)};
    for (const auto &[m, n] : {std::pair{axis, core::perp(axis)}, std::pair{aslant, core::perp(axis)}})
      for (const auto &c : cases)
        {
          const unsigned int nd = c.X.size();
          std::vector<double> grad(nd), gdummy(nd), X = c.X;
          std::vector<double> tangent(nd * nd);
          double U;
          ASSERT_TRUE(fem::channel_wall_element(c.pos, h, k, X.data(), m, n, U, grad.data(), tangent.data()));
          ASSERT_GT(U, 0.0);
          double scale = 0;
          for (const double gi : grad)
            scale = std::max(scale, std::abs(gi));
          for (unsigned int j = 0; j < nd; ++j)
            {
              const double e = 1e-6;
              double up, um;
              X[j] = c.X[j] + e;
              fem::channel_wall_element(c.pos, h, k, X.data(), m, n, up, gdummy.data());
              X[j] = c.X[j] - e;
              fem::channel_wall_element(c.pos, h, k, X.data(), m, n, um, gdummy.data());
              X[j] = c.X[j];
              EXPECT_NEAR(grad[j], (up - um) / (2 * e), 1e-6 * scale) << "dof " << j;
            }
          double tangent_scale = 0;
          for (const double t : tangent)
            tangent_scale = std::max(tangent_scale, std::abs(t));
          std::vector<double> gp(nd), gm(nd);
          for (unsigned int j = 0; j < nd; ++j)
            {
              const double e = 1e-5;
              double dummy;
              X[j] = c.X[j] + e;
              fem::channel_wall_element(c.pos, h, k, X.data(), m, n, dummy, gp.data());
              X[j] = c.X[j] - e;
              fem::channel_wall_element(c.pos, h, k, X.data(), m, n, dummy, gm.data());
              X[j] = c.X[j];
              for (unsigned int i = 0; i < nd; ++i)
                EXPECT_NEAR(tangent[i * nd + j], (gp[i] - gm[i]) / (2 * e), 1e-5 * tangent_scale)
                    << "entry " << i << ", " << j;
            }
        }
    // Inside, degree 1: (k h/2)(ya^2 + ya yb + yb^2)/3.
    const std::vector<double> X{-2.0, 0.05, -1.0, -0.07};
    double U;
    std::vector<double> grad(4);
    fem::channel_wall_element({0.0, 1.0}, h, k, X.data(), axis, core::perp(axis), U, grad.data());
    const double expected = 0.5 * k * h * (0.0025 - 0.0035 + 0.0049) / 3.0;
    EXPECT_NEAR(U, expected, 1e-12 * expected);
    // Wholly outside.
    const std::vector<double> out{0.2, 0.3, 1.1, 0.0};
    EXPECT_FALSE(
        fem::channel_wall_element({0.0, 1.0}, h, k, out.data(), axis, core::perp(axis), U, grad.data()));
  }

  TEST(RodElement, TangentIsTheDerivativeOfTheResidual)
  {
    std::mt19937 gen(5);
    for (unsigned int p = 1; p <= 3; ++p)
      {
        const auto shape = fem::ElementShape::lagrange(p, 0.8, p);
        const auto dofs = random_dofs(shape, gen);
        const auto old = random_states(p, gen);
        // Elastic; elastoplastic with yielding; with the viscous dashpots.
        expect_tangent_matches_residual(shape, material::MomentCurvatureLaw(60.0), section(), 0.0, dofs, old);
        const auto law = plastic_law(0.01);
        fem::ElementResult r;
        fem::evaluate_rod_element(shape, section(), law, dofs.data(), old.data(), 0.0, false, r);
        EXPECT_GT(r.plastic_work, 0.0) << "the plastic case does not yield";
        expect_tangent_matches_residual(shape, law, section(), 0.0, dofs, old);
        expect_tangent_matches_residual(shape, law, section(3.0, 0.5), 0.05, dofs, old);
      }
  }

  TEST(RodElement, HandDerivedTangentAgreesWithAutomaticDifferentiation)
  {
    std::mt19937 gen(11);
    for (unsigned int p = 1; p <= 3; ++p)
      for (int trial = 0; trial < 20; ++trial)
        {
          const auto shape = fem::ElementShape::lagrange(p, 0.8, p);
          const auto dofs = random_dofs(shape, gen, 0.3);
          const auto old = random_states(p, gen);
          for (const auto &law : {material::MomentCurvatureLaw(60.0), plastic_law(0.01)})
            for (const double dt : {0.0, 0.05})
              for (const double viscous_scale : {1.0, 0.3})
                {
                  fem::ElementResult r;
                  fem::evaluate_rod_element(shape, section(3.0, 0.5), law, dofs.data(), old.data(), dt, true,
                                            r, viscous_scale);
                  const auto ad = fem::rod_element_tangent_by_ad(shape, section(3.0, 0.5), law, dofs.data(),
                                                                 old.data(), dt, viscous_scale);
                  double largest = 0.0, worst = 0.0;
                  for (std::size_t i = 0; i < ad.size(); ++i)
                    {
                      largest = std::max(largest, std::abs(ad[i]));
                      worst = std::max(worst, std::abs(ad[i] - r.tangent[i]));
                    }
                  EXPECT_LT(worst, 1e-10 * largest) << "p = " << p << ", dt = " << dt;
                }
        }
  }

  TEST(RodElement, RigidRotationBy90DegreesGivesNoStrainAndNoForce)
  {
    for (unsigned int p = 1; p <= 3; ++p)
      {
        const auto shape = fem::ElementShape::lagrange(p, 2.0, p);
        std::vector<double> dofs(3 * shape.n_nodes);
        for (unsigned int a = 0; a < shape.n_nodes; ++a)
          {
            const double S = shape.node_position[a] * shape.length;
            // (S, 0) rotated by 90 degrees and moved: (3 - 0, 7 + S), theta = pi/2.
            dofs[3 * a] = 3.0;
            dofs[3 * a + 1] = 7.0 + S;
            dofs[3 * a + 2] = M_PI / 2;
          }
        const std::vector<fem::PointState> old(p);
        fem::ElementResult r;
        fem::evaluate_rod_element(shape, section(), plastic_law(), dofs.data(), old.data(), 0.0, false, r);
        for (const double f : r.residual)
          EXPECT_NEAR(f, 0.0, 1e-10);
        for (const auto &s : r.state)
          {
            EXPECT_NEAR(s.axial_strain, 0.0, 1e-14);
            EXPECT_NEAR(s.shear_strain, 0.0, 1e-14);
            EXPECT_NEAR(s.curvature, 0.0, 1e-14);
          }
        EXPECT_NEAR(r.axial_energy + r.shear_energy + r.bending_energy, 0.0, 1e-20);
      }
  }

  // Cantilever clamped at S = 0 with a transverse tip load, solved
  // statically by Newton on the element kernel. Returns the tip deflection.
  double cantilever_tip(unsigned int p, unsigned int n_el, unsigned int nq, double L, double P, double EI,
                        const fem::SectionProperties &sec)
  {
    const auto shape = fem::ElementShape::lagrange(p, L / n_el, nq);
    const unsigned int n_nodes = n_el * p + 1, n = 3 * n_nodes;
    auto node = [&](unsigned int e, unsigned int a) {
      return a == 0 ? e * p : a == 1 ? (e + 1) * p : e * p + a - 1;
    };
    dealii::Vector<double> u(n);
    for (unsigned int e = 0; e < n_el; ++e)
      for (unsigned int a = 0; a <= p; ++a)
        u[3 * node(e, a)] = (e + shape.node_position[a]) * shape.length;
    const material::MomentCurvatureLaw law(EI);
    const std::vector<fem::PointState> old(nq);
    for (int it = 0; it < 20; ++it)
      {
        dealii::Vector<double> r(n);
        dealii::FullMatrix<double> K(n, n);
        fem::ElementResult er;
        for (unsigned int e = 0; e < n_el; ++e)
          {
            std::vector<double> ue(3 * (p + 1));
            for (unsigned int a = 0; a <= p; ++a)
              for (unsigned int c = 0; c < 3; ++c)
                ue[3 * a + c] = u[3 * node(e, a) + c];
            fem::evaluate_rod_element(shape, sec, law, ue.data(), old.data(), 0.0, true, er);
            for (unsigned int i = 0; i < ue.size(); ++i)
              {
                const unsigned int gi = 3 * node(e, i / 3) + i % 3;
                r[gi] += er.residual[i];
                for (unsigned int j = 0; j < ue.size(); ++j)
                  K(gi, 3 * node(e, j / 3) + j % 3) += er.tangent[i * ue.size() + j];
              }
          }
        r[3 * (n_nodes - 1) + 1] -= P;
        for (unsigned int c = 0; c < 3; ++c) // clamp node 0
          {
            for (unsigned int j = 0; j < n; ++j)
              K(c, j) = K(j, c) = 0.0;
            K(c, c) = 1.0;
            r[c] = 0.0;
          }
        if (r.linfty_norm() < 1e-10 * P + 1e-13)
          break;
        K.gauss_jordan();
        dealii::Vector<double> du(n);
        K.vmult(du, r);
        u -= du;
      }
    return u[3 * (n_nodes - 1) + 1];
  }

  TEST(RodElement, NoLockingAtSlenderness1e4)
  {
    const auto sec = section();
    const double EI = 60.0;
    const double L = 1e4 * std::sqrt(EI / sec.EA); // slenderness L / radius of gyration
    const double P = 3e-4 * EI / (L * L);          // tip deflection 1e-4 L: linear range
    const double exact = P * L * L * L / (3 * EI) + P * L / sec.GA;
    // Reduced integration (p points) converges with order 2 for p = 1 ...
    double err[3];
    for (int k = 0; k < 3; ++k)
      err[k] = std::abs(cantilever_tip(1, 4u << k, 1, L, P, EI, sec) / exact - 1.0);
    EXPECT_LT(err[2], 0.01);
    for (int k = 0; k < 2; ++k)
      EXPECT_NEAR(std::log2(err[k] / err[k + 1]), 2.0, 0.15) << "convergence order of p = 1";
    // ... and is accurate already on a coarse mesh for p = 2, 3.
    for (unsigned int p = 2; p <= 3; ++p)
      EXPECT_NEAR(cantilever_tip(p, 4, p, L, P, EI, sec) / exact, 1.0, 1e-3) << "p = " << p;
    // Full integration locks: the rod is orders of magnitude too stiff.
    EXPECT_LT(cantilever_tip(1, 16, 2, L, P, EI, sec) / exact, 0.01);
  }

  TEST(RodElement, KirchhoffPenaltyRemovesTheShearDeflection)
  {
    auto sec = section();
    const double EI = 60.0, L = 20.0, P = 1e-4;
    const double bending = P * L * L * L / (3 * EI);
    sec.GA = 1000.0 * sec.EA;
    EXPECT_NEAR(cantilever_tip(2, 8, 2, L, P, EI, sec) / bending, 1.0, 1e-3);
  }

  fem::ContactSettings settings(bool friction)
  {
    fem::ContactSettings s;
    s.stiffness = 2000.0;
    s.friction = friction;
    s.mu_static = 0.6;
    s.mu_dynamic = 0.4;
    s.threshold_velocity = 0.01;
    return s;
  }

  // A wall contact at x: its tangent against central differences of its
  // residual and, without friction, its residual against those of its
  // energy (the force is the energy's gradient).
  void expect_wall_derivatives(const double R, const fem::ContactSettings &st, const Vec2 &x, const Vec2 &v0,
                               const double c, const bool friction)
  {
    fem::ContactContribution cc, cp, cm;
    ASSERT_TRUE(fem::wall_contact(R, st, 0.7, x, v0, c, cc));
    for (int j = 0; j < 2; ++j)
      {
        const double h = 1e-7;
        Vec2 xp = x, xm = x;
        (j ? xp.y : xp.x) += h;
        (j ? xm.y : xm.x) -= h;
        ASSERT_TRUE(fem::wall_contact(R, st, 0.7, xp, v0, c, cp));
        ASSERT_TRUE(fem::wall_contact(R, st, 0.7, xm, v0, c, cm));
        for (int i = 0; i < 2; ++i)
          EXPECT_NEAR((cp.residual[i] - cm.residual[i]) / (2 * h), cc.tangent[i * 2 + j],
                      1e-5 * std::abs(cc.tangent[i * 2 + j]) + 1e-6)
              << "at " << x.x << ", " << x.y;
        if (!friction)
          {
            EXPECT_NEAR((cp.energy - cm.energy) / (2 * h), cc.residual[j], 1e-6 * cc.normal_force);
          }
      }
  }

  TEST(FemContact, WallForceIsTheGradientAndTangentTheDerivative)
  {
    const double R = 10.0;
    for (const Vec2 x : {Vec2{3.0, 9.35}, Vec2{-9.9, 0.2} /* at a mouth corner, if any */})
      for (const bool friction : {false, true})
        for (const bool mouths : {true, false})
          {
            const Vec2 v0{0.003, -0.002};
            const double c = 40.0;
            auto st = settings(friction);
            st.mouths = mouths;
            fem::ContactContribution cc;
            ASSERT_TRUE(fem::wall_contact(R, st, 0.7, x, v0, c, cc));
            if (!friction)
              {
                // Without mouths the wall pushes towards the centre, by k w (|x| + d/2 - R).
                const double radial = (cc.residual[0] * x.x + cc.residual[1] * x.y) / norm(x);
                const double tangential = (cc.residual[1] * x.x - cc.residual[0] * x.y) / norm(x);
                if (!mouths || x.x > 0.0)
                  {
                    EXPECT_NEAR(radial, st.stiffness * 0.7 * (norm(x) + 0.5 - R), 1e-9 * st.stiffness);
                    EXPECT_NEAR(tangential, 0.0, 1e-9 * st.stiffness);
                  }
                else
                  EXPECT_GT(std::abs(tangential), 0.01 * std::abs(radial))
                      << "the mouth's corner pushes aslant";
              }
            expect_wall_derivatives(R, st, x, v0, c, friction);
          }
  }

  /// A wall with its channels' mouths, the channels turned by `angle` degrees.
  std::shared_ptr<const injection::ChannelledWall> channelled(const geometry::Cavity &wall,
                                                              const double angle)
  {
    scene::InjectionParameters in;
    in.channel_angle = angle;
    return std::make_shared<const injection::ChannelledWall>(wall, scene::channel_mouths(wall, in));
  }

  /// An ellipse of aspect ratio 1.5 and mean radius R, channels turned 30 degrees.
  std::shared_ptr<const injection::ChannelledWall> turned_ellipse(const double R)
  {
    const double q = std::sqrt(1.5);
    return channelled(geometry::Cavity::ellipse(R * q, R / q), 30.0);
  }

  /// The point `depth` outside the wall at the fraction s of its length.
  Vec2 off_wall(const injection::ChannelledWall &wall, const double s, const double depth)
  {
    const auto w = wall.cavity.at(s * wall.cavity.perimeter());
    return w.point + depth * w.normal;
  }

  // Any wall (ContactSettings::shaped): on the circle with the paper's
  // mouths it is the closed form; on an ellipse with channels turned 30
  // degrees the force is the gradient of the energy and the tangent the
  // derivative of the residual, against the wall and at the mouths' corners.
  TEST(FemContact, ShapedWallIsTheCircleOnTheCircleAndItsTangentTheDerivative)
  {
    const double R = 10.0;
    for (const bool friction : {false, true})
      {
        auto plain = settings(friction), shaped = settings(friction);
        shaped.shaped = channelled(geometry::Cavity::circle(R), 0.0);
        const Vec2 v0{0.003, -0.002};
        for (const Vec2 x : {Vec2{3.0, 9.35}, Vec2{-9.9, 0.2}, Vec2{9.8, -0.25}, Vec2{-6.0, -7.7}})
          {
            fem::ContactContribution a, b;
            ASSERT_TRUE(fem::wall_contact(R, plain, 0.7, x, v0, 40.0, a));
            ASSERT_TRUE(fem::wall_contact(R, shaped, 0.7, x, v0, 40.0, b));
            for (int i = 0; i < 2; ++i)
              EXPECT_NEAR(a.residual[i], b.residual[i], 1e-9 * plain.stiffness);
            for (int i = 0; i < 4; ++i)
              EXPECT_NEAR(a.tangent[i], b.tangent[i], 1e-9 * plain.stiffness);
          }
      }
    const auto wall = turned_ellipse(R);
    const auto &m = wall->mouths;
    const auto at_wall = [&](const double s, const double depth) { return off_wall(*wall, s, depth); };
    for (const bool friction : {false, true})
      for (const Vec2 x : {at_wall(0.2, 0.3), at_wall(0.63, 0.1), m[0].corners[0] + 0.3 * m[0].axis,
                           m[1].corners[1] + 0.2 * m[1].axis + 0.1 * core::perp(m[1].axis)})
        {
          auto st = settings(friction);
          st.shaped = wall;
          expect_wall_derivatives(R, st, x, Vec2{0.003, -0.002}, 40.0, friction);
        }
  }

  TEST(FemContact, SpringLawWallTangentIsTheDerivativeAndItsForceTheDiscreteLaw)
  {
    // Sticking (small step), sliding (large step) and sliding on (old state
    // sliding, fast): in each the tangent is the derivative of the residual
    // within the branch, and the friction force and history are those of
    // contact::friction_update for the same normal force and tangential
    // displacement.
    const double R = 10.0, dt = 0.1, ratio = 0.2, w = 0.7;
    const Vec2 x{3.0, 9.35};
    struct Case
    {
      Vec2 step;
      contact::FrictionHistory old;
      bool sliding;
    };
    // Here F_n = 2000 w 0.32 = 448: the static cap mu_st F_n / k_t is 0.96 d of
    // elongation, the dynamic one 0.64 d.
    for (const auto &c :
         {Case{{1e-5, -3e-6}, {2e-5, false}, false}, Case{{1.5, -0.48}, {0.0, false}, true},
          Case{{0.02, -0.006}, {-0.64, true}, true}, Case{{0.02, -0.006}, {-0.3, true}, false}})
      {
        const Vec2 x_old = x - c.step;
        fem::ContactContribution cc, cp, cm, normal;
        fem::SpringFriction sf, tmp;
        ASSERT_TRUE(fem::wall_contact_spring(R, settings(true), w, ratio, x, x_old, dt, c.old, cc, sf));
        EXPECT_EQ(sf.history.sliding, c.sliding);
        // The same through the discrete model's law.
        ASSERT_TRUE(fem::wall_contact(R, settings(false), w, x, Vec2{}, 0.0, normal));
        const Vec2 n = (1.0 / norm(x)) * x, t{-n.y, n.x};
        contact::FrictionCoefficients fc{0.6, 0.4, 0.01, ratio * 2000.0 * w};
        const auto law = contact::friction_update(fc, normal.normal_force, dot(c.step, t) / dt, dt, c.old);
        EXPECT_NEAR(sf.history.elongation, law.history.elongation, 1e-12);
        EXPECT_EQ(sf.history.sliding, law.history.sliding);
        EXPECT_NEAR(sf.dissipated, law.dissipated, 1e-12);
        EXPECT_NEAR(sf.stored,
                    0.5 * fc.tangential_stiffness * law.history.elongation * law.history.elongation, 1e-12);
        for (int i = 0; i < 2; ++i)
          EXPECT_NEAR(cc.friction_residual[i], -law.force * (i ? t.y : t.x), 1e-12);
        for (int j = 0; j < 2; ++j)
          {
            const double h = 1e-8;
            Vec2 xp = x, xm = x;
            (j ? xp.y : xp.x) += h;
            (j ? xm.y : xm.x) -= h;
            ASSERT_TRUE(fem::wall_contact_spring(R, settings(true), w, ratio, xp, x_old, dt, c.old, cp, tmp));
            ASSERT_TRUE(fem::wall_contact_spring(R, settings(true), w, ratio, xm, x_old, dt, c.old, cm, tmp));
            for (int i = 0; i < 2; ++i)
              EXPECT_NEAR((cp.residual[i] - cm.residual[i]) / (2 * h), cc.tangent[i * 2 + j],
                          1e-5 * std::abs(cc.tangent[i * 2 + j]) + 1e-5)
                  << i << j;
          }
      }
  }

  // The wall under the spring law, derived by hand, against the same law by
  // automatic differentiation: on the circle, at its mouths' corners and on
  // a shaped wall (an ellipse with turned channels, against the wall and at
  // a corner); sticking and sliding; the friction weighted in the tangent.
  TEST(FemContact, SpringLawWallByHandIsTheAutomaticDerivative)
  {
    const double R = 10.0, dt = 0.1, ratio = 0.2;
    const auto wall = turned_ellipse(R);
    const auto at_wall = [&](const double s, const double depth) { return off_wall(*wall, s, depth); };
    const double corner_x = std::sqrt(R * R - 0.25);
    struct Place
    {
      Vec2 x;
      bool shaped;
    };
    const std::vector<Place> places{{{3.0, 9.35}, false},
                                    {{-6.0, -7.7}, false},
                                    {{corner_x + 0.1, 0.2}, false},
                                    {{-corner_x - 0.2, -0.15}, false},
                                    {at_wall(0.2, 0.3), true},
                                    {at_wall(0.63, 0.1), true},
                                    {wall->mouths[0].corners[0] + 0.3 * wall->mouths[0].axis, true}};
    std::mt19937 gen(11);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02);
    int sliding = 0, sticking = 0;
    for (const auto &place : places)
      for (const bool friction : {false, true})
        for (const double step : {1e-4, 0.05, 1.5})
          for (const contact::FrictionHistory old :
               {contact::FrictionHistory{0.01, false}, contact::FrictionHistory{-0.3, true}})
            {
              auto st = settings(friction);
              if (place.shaped)
                st.shaped = wall;
              const Vec2 x = place.x + Vec2{jitter(gen), jitter(gen)};
              const Vec2 x_old = x - Vec2{step, -0.4 * step};
              fem::ContactContribution hand, ad, lean;
              fem::SpringFriction f_hand, f_ad, f_lean;
              const double scale = 1.7;
              const bool touches =
                  fem::wall_contact_spring(R, st, 0.7, ratio, x, x_old, dt, old, hand, f_hand, scale);
              ASSERT_EQ(touches, fem::wall_contact_spring_by_ad(R, st, 0.7, ratio, x, x_old, dt, old, ad,
                                                                f_ad, scale));
              ASSERT_TRUE(touches) << x.x << " " << x.y;
              lean.want_tangent = false;
              ASSERT_TRUE(
                  fem::wall_contact_spring(R, st, 0.7, ratio, x, x_old, dt, old, lean, f_lean, scale));
              const double size = st.stiffness;
              for (int i = 0; i < 2; ++i)
                {
                  EXPECT_NEAR(hand.residual[i], ad.residual[i], 1e-12 * size);
                  EXPECT_NEAR(hand.friction_residual[i], ad.friction_residual[i], 1e-12 * size);
                  EXPECT_EQ(lean.residual[i], hand.residual[i]);
                }
              for (int i = 0; i < 4; ++i)
                {
                  EXPECT_NEAR(hand.tangent[i], ad.tangent[i], 1e-10 * std::abs(ad.tangent[i]) + 1e-12 * size)
                      << place.x.x << " " << place.x.y << " " << i;
                  EXPECT_EQ(lean.tangent[i], 0.0);
                }
              EXPECT_EQ(hand.overlap, ad.overlap);
              EXPECT_EQ(hand.normal_force, ad.normal_force);
              EXPECT_EQ(hand.energy, ad.energy);
              EXPECT_EQ(f_hand.history.elongation, f_ad.history.elongation);
              EXPECT_EQ(f_hand.history.sliding, f_ad.history.sliding);
              EXPECT_EQ(f_hand.dissipated, f_ad.dissipated);
              // Sliding: the friction force at its cap mu_d F_n.
              const double ft = norm(Vec2{hand.friction_residual[0], hand.friction_residual[1]});
              if (friction)
                ++(std::abs(ft - st.mu_dynamic * hand.normal_force) < 1e-9 * size ? sliding : sticking);
            }
    EXPECT_GT(sliding, 0);
    EXPECT_GT(sticking, 0);
  }

  TEST(FemContact, SpringLawSelfFrictionIsTheDiscreteLawAndItsTangentTheDerivative)
  {
    // A node against a segment under the spring law: sticking, breaking
    // free, sliding on, and against the segment's end (t clamped). The
    // force on the node is contact::friction_update's for the same normal
    // force and slip along the contact tangent, the segment's ends take the
    // reaction in the shares 1 - t and t, and the tangent is the
    // derivative of the residual (central differences).
    const double dt = 0.1, ratio = 0.2, w = 0.7;
    const auto s = settings(true);
    struct Case
    {
      Vec2 node, step; // where the node is, and how far it moved in the step
      contact::FrictionHistory old;
      bool sliding;
    };
    const std::array<Vec2, 3> seg_move{{Vec2{}, Vec2{0.01, -0.02}, Vec2{0.03, 0.01}}};
    for (const auto &c : {Case{{0.4, 0.85}, {1e-5, -3e-6}, {2e-5, false}, false},
                          Case{{0.4, 0.85}, {1.5, -0.2}, {0.0, false}, true},
                          Case{{0.4, 0.85}, {0.05, 0.01}, {-0.5, true}, true},
                          Case{{1.3, 0.7}, {2e-4, 1e-4}, {1e-4, false}, false}})
      {
        const std::array<Vec2, 3> x{{c.node, Vec2{0.0, 0.0}, Vec2{1.0, 0.1}}};
        std::array<Vec2, 3> x_old;
        for (int m = 0; m < 3; ++m)
          x_old[m] = x[m] - (m == 0 ? c.step : seg_move[m]);
        fem::ContactContribution cc, cp, cm, normal;
        fem::SpringFriction sf, tmp;
        ASSERT_TRUE(fem::point_segment_spring_friction(s, w, ratio, x, x_old, dt, c.old, cc, sf));
        EXPECT_EQ(sf.history.sliding, c.sliding);
        // The normal force and the contact's geometry from the contact kernel.
        double t;
        ASSERT_TRUE(
            fem::point_segment_contact(settings(false), w, x, {{Vec2{}, Vec2{}, Vec2{}}}, 0.0, normal, t));
        EXPECT_NEAR(cc.normal_force, normal.normal_force, 1e-12);
        const Vec2 q = x[1] + t * (x[2] - x[1]), n = (1.0 / norm(x[0] - q)) * (x[0] - q), tau{-n.y, n.x};
        const Vec2 slip_vec = (x[0] - x_old[0]) - ((1.0 - t) * (x[1] - x_old[1]) + t * (x[2] - x_old[2]));
        contact::FrictionCoefficients fc{0.6, 0.4, 0.01, ratio * 2000.0 * w};
        const auto law =
            contact::friction_update(fc, normal.normal_force, dot(slip_vec, tau) / dt, dt, c.old);
        EXPECT_NEAR(sf.history.elongation, law.history.elongation, 1e-12);
        EXPECT_EQ(sf.history.sliding, law.history.sliding);
        EXPECT_NEAR(sf.dissipated, law.dissipated, 1e-9);
        EXPECT_NEAR(sf.stored,
                    0.5 * fc.tangential_stiffness * law.history.elongation * law.history.elongation, 1e-9);
        const double share[3] = {1.0, -(1.0 - t), -t};
        for (int m = 0; m < 3; ++m)
          for (int a = 0; a < 2; ++a)
            {
              const double expected = -share[m] * law.force * (a ? tau.y : tau.x);
              EXPECT_NEAR(cc.residual[2 * m + a], expected, 1e-9 * std::abs(law.force) + 1e-12) << m << a;
              EXPECT_EQ(cc.friction_residual[2 * m + a], cc.residual[2 * m + a]);
            }
        for (int j = 0; j < 6; ++j)
          {
            const double h = 1e-7;
            auto xp = x, xm = x;
            (j % 2 ? xp[j / 2].y : xp[j / 2].x) += h;
            (j % 2 ? xm[j / 2].y : xm[j / 2].x) -= h;
            ASSERT_TRUE(fem::point_segment_spring_friction(s, w, ratio, xp, x_old, dt, c.old, cp, tmp));
            ASSERT_TRUE(fem::point_segment_spring_friction(s, w, ratio, xm, x_old, dt, c.old, cm, tmp));
            double scale = 0.0;
            for (int i = 0; i < 6; ++i)
              scale = std::max(scale, std::abs(cc.tangent[i * 6 + j]));
            for (int i = 0; i < 6; ++i)
              EXPECT_NEAR((cp.residual[i] - cm.residual[i]) / (2 * h), cc.tangent[i * 6 + j],
                          1e-5 * scale + 1e-6)
                  << "row " << i << ", column " << j;
          }
      }
    // Out of reach: no contribution.
    fem::ContactContribution none;
    fem::SpringFriction sf;
    const std::array<Vec2, 3> far{{Vec2{0.4, 1.2}, Vec2{0.0, 0.0}, Vec2{1.0, 0.1}}};
    EXPECT_FALSE(fem::point_segment_spring_friction(s, w, ratio, far, far, dt, {}, none, sf));
  }

  // The self contact's spring-law friction derived by hand against the same
  // law by automatic differentiation: nodes against the segment's middle and
  // past either end (t clamped), sticking and sliding, moving segments, the
  // friction weighted in the tangent; without a tangent the residual alone.
  TEST(FemContact, SpringLawSelfFrictionByHandIsTheAutomaticDerivative)
  {
    const double dt = 0.1, ratio = 0.2, w = 0.7, scale = 1.7;
    const auto s = settings(true);
    std::mt19937 gen(5);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    int sliding = 0, sticking = 0, clamped = 0, inside = 0;
    for (const Vec2 node : {Vec2{0.4, 0.85}, Vec2{0.7, -0.6}, Vec2{-0.3, 0.5}, Vec2{1.4, 0.6}})
      for (const double step : {1e-4, 0.05, 1.5})
        for (const contact::FrictionHistory old :
             {contact::FrictionHistory{0.01, false}, contact::FrictionHistory{-0.3, true}})
          {
            const std::array<Vec2, 3> x{{node + Vec2{jitter(gen), jitter(gen)},
                                         Vec2{jitter(gen), jitter(gen)},
                                         Vec2{1.0 + jitter(gen), 0.1 + jitter(gen)}}};
            const std::array<Vec2, 3> x_old{
                {x[0] - Vec2{step, -0.4 * step}, x[1] - Vec2{0.01, -0.02}, x[2] - Vec2{0.03 * step, 0.01}}};
            fem::ContactContribution hand, ad, lean;
            fem::SpringFriction f_hand, f_ad, f_lean;
            const bool touches =
                fem::point_segment_spring_friction(s, w, ratio, x, x_old, dt, old, hand, f_hand, scale);
            ASSERT_EQ(touches, fem::point_segment_spring_friction_by_ad(s, w, ratio, x, x_old, dt, old, ad,
                                                                        f_ad, scale));
            ASSERT_TRUE(touches) << node.x << " " << node.y;
            lean.want_tangent = false;
            ASSERT_TRUE(
                fem::point_segment_spring_friction(s, w, ratio, x, x_old, dt, old, lean, f_lean, scale));
            const double size = s.stiffness;
            for (int i = 0; i < 6; ++i)
              {
                EXPECT_NEAR(hand.residual[i], ad.residual[i], 1e-12 * size);
                EXPECT_EQ(hand.friction_residual[i], hand.residual[i]);
                EXPECT_EQ(lean.residual[i], hand.residual[i]);
              }
            for (int i = 0; i < 36; ++i)
              {
                EXPECT_NEAR(hand.tangent[i], ad.tangent[i], 1e-10 * std::abs(ad.tangent[i]) + 1e-12 * size)
                    << node.x << " " << node.y << " " << step << " " << i;
                EXPECT_EQ(lean.tangent[i], 0.0);
              }
            EXPECT_EQ(hand.overlap, ad.overlap);
            EXPECT_EQ(hand.normal_force, ad.normal_force);
            EXPECT_EQ(f_hand.history.elongation, f_ad.history.elongation);
            EXPECT_EQ(f_hand.history.sliding, f_ad.history.sliding);
            EXPECT_EQ(f_hand.dissipated, f_ad.dissipated);
            ++(f_hand.history.sliding ? sliding : sticking);
            // The node's projection on the segment's line, past an end or not.
            const Vec2 e = x[2] - x[1];
            const double t = dot(x[0] - x[1], e) / dot(e, e);
            ++(t <= 0.0 || t >= 1.0 ? clamped : inside);
          }
    EXPECT_GT(sliding, 0);
    EXPECT_GT(sticking, 0);
    EXPECT_GT(clamped, 0);
    EXPECT_GT(inside, 0);
  }

  // A contact on N points: its residual is the gradient of its energy
  // (without friction) and its tangent the derivative of its residual, by
  // central differences in every coordinate. contribution(x, out) is the
  // contact function at positions x.
  template <std::size_t N, typename Contribution>
  void expect_consistent_contact(const std::array<Vec2, N> &x, const bool friction,
                                 const Contribution &contribution)
  {
    constexpr int nd = 2 * N;
    fem::ContactContribution cc, cp, cm;
    ASSERT_TRUE(contribution(x, cc));
    for (int j = 0; j < nd; ++j)
      {
        const double h = 1e-7;
        auto xp = x, xm = x;
        (j % 2 ? xp[j / 2].y : xp[j / 2].x) += h;
        (j % 2 ? xm[j / 2].y : xm[j / 2].x) -= h;
        ASSERT_TRUE(contribution(xp, cp));
        ASSERT_TRUE(contribution(xm, cm));
        for (int i = 0; i < nd; ++i)
          EXPECT_NEAR((cp.residual[i] - cm.residual[i]) / (2 * h), cc.tangent[i * nd + j],
                      1e-5 * std::abs(cc.tangent[i * nd + j]) + 1e-5)
              << i << ", " << j;
        if (!friction)
          {
            EXPECT_NEAR((cp.energy - cm.energy) / (2 * h), cc.residual[j], 1e-6 * cc.normal_force) << j;
          }
      }
  }

  TEST(FemContact, SegmentForceIsTheGradientAndTangentTheDerivative)
  {
    // End point of B against the interior of A, and end against end.
    const std::array<Vec2, 4> v0{{{0.001, 0}, {0.002, 0.001}, {-0.003, 0}, {0, 0.002}}};
    for (const std::array<Vec2, 4> x : {std::array<Vec2, 4>{{{0, 0}, {1, 0.1}, {0.4, 0.8}, {0.7, 1.9}}},
                                        std::array<Vec2, 4>{{{0, 0}, {1, 0.1}, {1.5, 0.6}, {2.5, 1.0}}}})
      for (const bool friction : {false, true})
        expect_consistent_contact(x, friction,
                                  [&](const std::array<Vec2, 4> &y, fem::ContactContribution &out) {
                                    return fem::segment_contact(settings(friction), 1.0, y, v0, 40.0, out);
                                  });
  }

  TEST(FemContact, HandDerivedPointSegmentTangentAgreesWithAutomaticDifferentiation)
  {
    // Random points near random segments: interior and clamped closest
    // points, friction off and on (sticking and sliding velocities), and
    // the friction weighted in the tangent.
    std::mt19937 gen(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0), speed(-0.05, 0.05);
    int compared = 0, interior = 0;
    while (compared < 400)
      {
        const std::array<Vec2, 3> x{{{u(gen), u(gen)}, {u(gen), u(gen)}, {u(gen), u(gen)}}};
        const std::array<Vec2, 3> v0{
            {{speed(gen), speed(gen)}, {speed(gen), speed(gen)}, {speed(gen), speed(gen)}}};
        const bool friction = compared % 2;
        const double fs = compared % 4 == 3 ? 0.3 : 1.0, c = compared % 3 ? 40.0 : 0.0;
        fem::ContactContribution hand, ad;
        double th, ta;
        const bool touch = fem::point_segment_contact(settings(friction), 0.5, x, v0, c, hand, th, fs);
        ASSERT_EQ(touch, fem::point_segment_contact_by_ad(settings(friction), 0.5, x, v0, c, ad, ta, fs));
        if (!touch)
          continue;
        ++compared;
        interior += th > 0.0 && th < 1.0;
        EXPECT_EQ(th, ta);
        double largest = 0.0, worst = 0.0, rworst = 0.0, rlargest = 0.0;
        for (int i = 0; i < 36; ++i)
          {
            largest = std::max(largest, std::abs(ad.tangent[i]));
            worst = std::max(worst, std::abs(ad.tangent[i] - hand.tangent[i]));
          }
        for (int i = 0; i < 6; ++i)
          {
            rlargest = std::max(rlargest, std::abs(ad.residual[i]));
            rworst = std::max(rworst, std::abs(ad.residual[i] - hand.residual[i]) +
                                          std::abs(ad.friction_residual[i] - hand.friction_residual[i]));
          }
        EXPECT_LT(worst, 1e-10 * largest) << "friction " << friction << ", t = " << th;
        EXPECT_LT(rworst, 1e-12 * rlargest);
        EXPECT_NEAR(hand.energy, ad.energy, 1e-10 * ad.energy); // g = d - |x0 - q| in another order
      }
    EXPECT_GT(interior, 100);
    EXPECT_LT(interior, 380) << "too few clamped closest points";
  }

  TEST(FemContact, APointContactWithoutItsTangentHasTheSameForces)
  {
    // want_tangent = false (a residual-only evaluation) leaves the tangent
    // zero and every other output as it is with the tangent, bit for bit:
    // random points against a segment and its next node, with friction.
    std::mt19937 gen(29);
    std::uniform_real_distribution<double> u(-1.0, 1.0), speed(-0.05, 0.05);
    int touching = 0, vertex = 0;
    for (int trial = 0; trial < 400; ++trial)
      {
        const std::array<Vec2, 3> x{{{u(gen), u(gen)}, {u(gen), u(gen)}, {u(gen), u(gen)}}};
        const std::array<Vec2, 3> v0{
            {{speed(gen), speed(gen)}, {speed(gen), speed(gen)}, {speed(gen), speed(gen)}}};
        fem::ContactContribution with, without;
        without.want_tangent = false;
        double t_with, t_without, f_with, f_without;
        const bool touch =
            fem::point_stretch_contact(settings(true), 0.5, x, v0, 40.0, true, with, t_with, f_with, 0.3);
        ASSERT_EQ(touch, fem::point_stretch_contact(settings(true), 0.5, x, v0, 40.0, true, without,
                                                    t_without, f_without, 0.3));
        if (!touch)
          continue;
        ++touching;
        vertex += f_with > 0.0;
        EXPECT_FALSE(without.want_tangent);
        EXPECT_EQ(t_with, t_without);
        EXPECT_EQ(f_with, f_without);
        EXPECT_EQ(with.residual, without.residual);
        EXPECT_EQ(with.friction_residual, without.friction_residual);
        EXPECT_EQ(with.energy, without.energy);
        EXPECT_EQ(with.normal_force, without.normal_force);
        EXPECT_EQ(with.overlap, without.overlap);
        EXPECT_TRUE(
            std::all_of(without.tangent.begin(), without.tangent.end(), [](double v) { return v == 0; }));
        // (At t = 1 the next node's contact takes the segment's back: zero.)
        if (t_with < 1.0)
          {
            EXPECT_TRUE(
                std::any_of(with.tangent.begin(), with.tangent.end(), [](double v) { return v != 0; }));
          }
      }
    EXPECT_GT(touching, 50);
    EXPECT_GT(vertex, 5) << "too few contacts where the next node presses too";
  }

  TEST(FemContact, PointForceIsTheGradientAndTangentTheDerivative)
  {
    const std::array<Vec2, 2> x{{{0.1, 0.2}, {0.7, 0.9}}};
    const std::array<Vec2, 2> v0{{{0.001, -0.002}, {0.003, 0.001}}};
    fem::ContactContribution cc;
    ASSERT_TRUE(fem::point_point_contact(settings(false), 0.5, x, v0, 40.0, cc));
    EXPECT_NEAR(cc.overlap, 1.0 - norm(x[0] - x[1]), 1e-15);
    EXPECT_NEAR(cc.energy, 0.25 * settings(false).stiffness * cc.overlap * cc.overlap, 1e-12);
    for (const bool friction : {false, true})
      expect_consistent_contact(x, friction,
                                [&](const std::array<Vec2, 2> &y, fem::ContactContribution &out) {
                                  return fem::point_point_contact(settings(friction), 0.5, y, v0, 40.0, out);
                                });
  }

  // The contact of point p with the polyline `wire` as the rod model
  // assembles it: every segment through point_stretch_contact, each but the
  // last with its next segment pressing too. Energy and the residual on p
  // and on the wire's nodes (p first).
  struct StretchContact
  {
    double energy = 0.0;
    std::vector<double> residual;
    std::vector<double> tangent; ///< row major, square
    int n_touching = 0;
  };

  StretchContact stretch_contact(const Vec2 &p, const std::vector<Vec2> &wire, const bool friction = false,
                                 const std::vector<Vec2> &v0 = {})
  {
    const int n = static_cast<int>(wire.size()), nd = 2 * (n + 1);
    StretchContact r;
    r.residual.assign(nd, 0.0);
    r.tangent.assign(nd * nd, 0.0);
    for (int s = 0; s + 1 < n; ++s)
      {
        const auto vel = [&](int k) { return v0.empty() ? Vec2{0, 0} : v0[k]; };
        fem::ContactContribution cc;
        double t, fv;
        if (!fem::point_stretch_contact(settings(friction), 0.5, {{p, wire[s], wire[s + 1]}},
                                        {{vel(0), vel(s + 1), vel(s + 2)}}, 40.0, s + 2 < n, cc, t, fv))
          continue;
        ++r.n_touching;
        r.energy += cc.energy;
        const int ids[3] = {0, s + 1, s + 2}; // points: p, then the wire's nodes
        for (int a = 0; a < 6; ++a)
          {
            const int ga = 2 * ids[a / 2] + a % 2;
            r.residual[ga] += cc.residual[a];
            for (int b = 0; b < 6; ++b)
              r.tangent[ga * nd + 2 * ids[b / 2] + b % 2] += cc.tangent[a * 6 + b];
          }
      }
    return r;
  }

  TEST(FemContact, AStretchPressesAPointOnceOnItsStraightPartAndOuterSide)
  {
    const double k = 0.5 * settings(false).stiffness;
    // Straight wire of uneven segments: p at height 0.97 feels one contact
    // of overlap 0.03 wherever it is along it, past nodes too.
    const std::vector<Vec2> straight{{0, 0}, {1, 0}, {1.7, 0}, {2.9, 0}, {3.5, 0}, {4.6, 0}, {6, 0}};
    int near_a_node = 0; // samples where two segments reach p
    for (double a = 1.0; a <= 5.0; a += 0.0137)
      {
        const auto r = stretch_contact({a, 0.97}, straight);
        near_a_node += r.n_touching >= 2;
        EXPECT_NEAR(r.energy, 0.5 * k * 0.03 * 0.03, 1e-12) << "at " << a;
        EXPECT_NEAR(r.residual[0], 0.0, 1e-9) << "at " << a;
        EXPECT_NEAR(r.residual[1], -k * 0.03, 1e-9) << "at " << a;
      }
    EXPECT_GT(near_a_node, 40);
    // Outer side of a bend (the wire turns away from p): near the node p
    // feels the node alone.
    const double beta = 0.15;
    const std::vector<Vec2> bent{{-2 * std::cos(beta), -2 * std::sin(beta)},
                                 {-std::cos(beta), -std::sin(beta)},
                                 {0, 0},
                                 {std::cos(beta), -std::sin(beta)},
                                 {2 * std::cos(beta), -2 * std::sin(beta)}};
    for (const Vec2 p : {Vec2{0.0, 0.96}, Vec2{0.05, 0.95}, Vec2{-0.1, 0.9}})
      {
        const auto r = stretch_contact(p, bent);
        const double g = 1.0 - norm(p);
        EXPECT_NEAR(r.energy, 0.5 * k * g * g, 1e-12);
        EXPECT_NEAR(r.residual[0], -k * g * p.x / norm(p), 1e-9);
        EXPECT_NEAR(r.residual[1], -k * g * p.y / norm(p), 1e-9);
      }
  }

  TEST(FemContact, TheForceOfAStretchIsSmoothInTheCreaseOfABend)
  {
    // p on the inner side of a wire bent by 0.3 at node 2, on the bisector
    // of the crease and just beside it, at two depths (the node itself
    // within reach and not).
    const double beta = 0.15, h = 1e-7;
    const std::vector<Vec2> wire{{-2 * std::cos(beta), 2 * std::sin(beta)},
                                 {-std::cos(beta), std::sin(beta)},
                                 {0, 0},
                                 {std::cos(beta), std::sin(beta)},
                                 {2 * std::cos(beta), 2 * std::sin(beta)}};
    for (const double gap : {0.97, 0.995})
      {
        const double y = gap / std::cos(beta);
        const auto left = stretch_contact({-1e-9, y}, wire), right = stretch_contact({1e-9, y}, wire);
        const double f = std::hypot(left.residual[0], left.residual[1]);
        ASSERT_GT(f, 0.0);
        EXPECT_LT(std::hypot(left.residual[0] - right.residual[0], left.residual[1] - right.residual[1]),
                  1e-6 * f)
            << "the force on p jumps across the crease";
        // The rule that keeps the nearest segment only: its force on p turns
        // by the bend's angle across the crease (what the test guards).
        fem::ContactContribution a, b;
        double t;
        ASSERT_TRUE(fem::point_segment_contact(settings(false), 0.5, {{{-1e-9, y}, wire[1], wire[2]}}, {},
                                               0.0, a, t));
        ASSERT_TRUE(
            fem::point_segment_contact(settings(false), 0.5, {{{1e-9, y}, wire[2], wire[3]}}, {}, 0.0, b, t));
        EXPECT_GT(std::hypot(a.residual[0] - b.residual[0], a.residual[1] - b.residual[1]),
                  0.2 * a.normal_force);

        // Residual: the gradient of the energy; tangent: the derivative of
        // the residual, in all 12 coordinates, on and beside the bisector,
        // without friction and with it.
        for (const double off : {0.0, 0.02, -0.05})
          for (const bool friction : {false, true})
            {
              const Vec2 p{off, y};
              std::vector<Vec2> v0{{0.001, -0.002}, {0.0, 0.001}, {0.002, 0.0}, {-0.001, 0.0}, {0.0, 0.0}};
              const auto r = stretch_contact(p, wire, friction, v0);
              const int nd = static_cast<int>(r.residual.size());
              for (int j = 0; j < nd; ++j)
                {
                  auto pp = p, pm = p;
                  auto wp = wire, wm = wire;
                  const auto bump = [j](Vec2 &q, std::vector<Vec2> &w, const double d) {
                    Vec2 &c = j < 2 ? q : w[j / 2 - 1];
                    (j % 2 ? c.y : c.x) += d;
                  };
                  bump(pp, wp, h);
                  bump(pm, wm, -h);
                  const auto rp = stretch_contact(pp, wp, friction, v0),
                             rm = stretch_contact(pm, wm, friction, v0);
                  if (!friction)
                    {
                      EXPECT_NEAR((rp.energy - rm.energy) / (2 * h), r.residual[j], 1e-6 * f)
                          << "gap " << gap << " offset " << off << " coordinate " << j;
                    }
                  for (int i = 0; i < nd; ++i)
                    EXPECT_NEAR((rp.residual[i] - rm.residual[i]) / (2 * h), r.tangent[i * nd + j],
                                1e-5 * std::abs(r.tangent[i * nd + j]) + 1e-4)
                        << "gap " << gap << " offset " << off << " friction " << friction << " (" << i << ", "
                        << j << ")";
                }
            }
      }
  }

  // A point of mass m pressed against the wall by P and pulled along it by
  // T, integrated by backward Euler with Newton on the contact law.
  double slide(double T, double P, double time, double &max_speed)
  {
    const double R = 1e4, m = 1.0, dt = 1e-3; // a nearly flat wall
    const auto s = settings(true);
    Vec2 x{0.0, R - 0.5 + P / s.stiffness}, v{0, 0};
    max_speed = 0;
    for (double t = 0; t < time; t += dt)
      {
        Vec2 x1 = x;
        for (int it = 0; it < 30; ++it)
          {
            // m (x1 - x - dt v) / dt^2 + r(x1, v1) - F = 0, v1 = (x1 - x) / dt.
            fem::ContactContribution cc;
            const Vec2 v0 = -(1.0 / dt) * x;
            if (!fem::wall_contact(R, s, 1.0, x1, v0, 1.0 / dt, cc))
              {
                cc = fem::ContactContribution{};
              }
            const double g[2] = {m * (x1.x - x.x - dt * v.x) / (dt * dt) + cc.residual[0] - T,
                                 m * (x1.y - x.y - dt * v.y) / (dt * dt) + cc.residual[1] - P};
            double J[4] = {m / (dt * dt) + cc.tangent[0], cc.tangent[1], cc.tangent[2],
                           m / (dt * dt) + cc.tangent[3]};
            const double det = J[0] * J[3] - J[1] * J[2];
            x1.x -= (J[3] * g[0] - J[1] * g[1]) / det;
            x1.y -= (-J[2] * g[0] + J[0] * g[1]) / det;
            if (std::abs(g[0]) + std::abs(g[1]) < 1e-10)
              break;
          }
        v = (1.0 / dt) * (x1 - x);
        x = x1;
        max_speed = std::max(max_speed, std::abs(v.x));
      }
    return v.x;
  }

  TEST(FemContact, FrictionSticksBelowMuStaticAndSlidesWithMuDynamicAbove)
  {
    const double P = 10.0, time = 2.0;
    double vmax;
    // Below mu_st P: the point creeps at a fraction of v_th (stick).
    slide(0.5 * 0.6 * P, P, time, vmax);
    EXPECT_LT(vmax, 0.01);
    // Above mu_st P: it slides and accelerates at (T - mu_d P) / m.
    const double T = 1.2 * 0.6 * P;
    const double v = slide(T, P, time, vmax);
    EXPECT_NEAR(v / ((T - 0.4 * P) * time), 1.0, 0.02);
  }

  scene::Scene fem_scene(std::vector<std::string> extra = {})
  {
    std::vector<std::string> o = {"Model=fem", "Cavity/Radius=6", "Injection/Speed=1", "Output/Progress=off",
                                  "Contact/Friction/Static coefficient=0.3"};
    o.insert(o.end(), extra.begin(), extra.end());
    return scene::read_scene("", o);
  }

  /// The elastoplastic wire with friction, wall and self contact of the
  /// comparisons between two solver settings, with one or two more keys. Their
  /// steps are fixed (FEM/Step error = 0): the error control would set
  /// each run's steps from estimates that differ by rounding, and the runs
  /// would never meet at equal times. Newton stops at 1e-8 of EA, not the
  /// scenes' 1e-6, so that what it leaves does not hide a difference
  /// between the solvers (two solvers' wires differ by 2e-5 d at 1e-6).
  scene::Scene contact_scene(const std::string &key, const std::string &other = {})
  {
    std::vector<std::string> keys{"Wire/Plasticity/Yield curvature=0.05",
                                  "Contact/Friction/Static coefficient=0.5", "FEM/Step error=0",
                                  "FEM/Newton tolerance=1e-8", key};
    if (!other.empty())
      keys.push_back(other);
    return fem_scene(keys);
  }

  /// The largest distance between corresponding nodes of two wires (d).
  double largest_distance(const fem::RodModel &m1, const fem::RodModel &m2)
  {
    const auto a = m1.wire_state(), b = m2.wire_state();
    EXPECT_EQ(a.points.size(), b.points.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < std::min(a.points.size(), b.points.size()); ++k)
      worst = std::max(worst, std::hypot(a.points[k].x - b.points[k].x, a.points[k].y - b.points[k].y));
    return worst;
  }

  /// Steps both runs until a has injected `until`, expecting the same
  /// steps: the largest distance between their wires after any step (d),
  /// infinite when they took different steps.
  double in_step(fem::RodModel &a, fem::RodModel &b, const double until)
  {
    double worst = 0.0;
    while (a.injected_length() < until)
      {
        a.step();
        b.step();
        if (a.time() != b.time())
          {
            ADD_FAILURE() << "the runs took different steps at step " << a.n_steps();
            return INFINITY;
          }
        worst = std::max(worst, largest_distance(a, b));
      }
    return worst;
  }

  /// Two runs of the same scene stepped to injected length `until`, the
  /// one behind first (they may cut different steps): the largest distance
  /// between their wires wherever they reach the same time (expected at
  /// more than 500 times, with contacts in the runs).
  double at_equal_times(fem::RodModel &a, fem::RodModel &b, const double until)
  {
    int compared = 0;
    double worst = 0.0;
    while (a.injected_length() < until)
      {
        if (b.time() < a.time())
          b.step();
        else
          a.step();
        if (a.time() != b.time())
          continue;
        worst = std::max(worst, largest_distance(a, b));
        ++compared;
      }
    EXPECT_GT(a.report().n_self_contacts + a.report().n_wall_contacts, 0);
    EXPECT_GT(compared, 500) << "states at equal times";
    return worst;
  }

  TEST(RodModel, NewtonToleranceFollowsTheIntegratorUnlessSet)
  {
    // FEM/Newton tolerance = 0 (the default): 1e-6 of EA (1000 here) with
    // generalized-alpha, 1e-8 with quasi-static steps; a value set holds
    // under either.
    const auto tolerance = [](const std::vector<std::string> &keys) {
      return fem::RodModelProbe::newton_tolerance(fem::RodModel(fem_scene(keys)));
    };
    EXPECT_DOUBLE_EQ(tolerance({}), 1e-3);
    EXPECT_DOUBLE_EQ(tolerance({"FEM/Integrator=quasi-static"}), 1e-5);
    EXPECT_DOUBLE_EQ(tolerance({"FEM/Newton tolerance=1e-7"}), 1e-4);
    EXPECT_DOUBLE_EQ(tolerance({"FEM/Newton tolerance=1e-7", "FEM/Integrator=quasi-static"}), 1e-4);
  }

  TEST(RodModel, NewtonConvergesQuadratically)
  {
    // Order estimates log(e_{k+1}/e_k) / log(e_k/e_{k-1}) from the last three
    // residuals of every step that needed at least three iterations, once in
    // the asymptotic range (the first of the three a tenth of the
    // predictor's). A contact that switches on or off during the iterations
    // spoils single estimates; the median is quadratic. With an LU of every
    // tangent: GMRES on kept factors stops at half the Newton tolerance, so
    // its last iteration is not quadratic by design.
    fem::RodModel m(fem_scene({"FEM/Linear solver=refactorise"}));
    std::vector<double> orders;
    while (m.injected_length() < 45.0)
      {
        m.step();
        const auto &h = m.newton_history();
        const auto n = h.size();
        if (n >= 4 && h[n - 3] < 0.1 * h[0])
          orders.push_back(std::log(h[n - 1] / h[n - 2]) / std::log(h[n - 2] / h[n - 3]));
      }
    ASSERT_GE(orders.size(), 5u) << "too few steps with enough Newton iterations";
    std::sort(orders.begin(), orders.end());
    const double median = orders[orders.size() / 2];
    EXPECT_GT(median, 1.8) << orders.size() << " steps, lowest " << orders.front() << ", highest "
                           << orders.back();
    std::cout << "Newton order: median " << median << " over " << orders.size() << " steps\n";
  }

  /// Steps m until injected length `until` and checks the assembled
  /// tangent against finite differences at three steps with wall and self
  /// contact.
  void check_tangent_in_contact(fem::RodModel &m, const double until)
  {
    int checked = 0;
    while (m.injected_length() < until && checked < 3)
      {
        m.step();
        if (m.report().n_self_contacts > 0 && m.report().n_wall_contacts > 0 && m.n_steps() % 7 == 0)
          {
            const double err = fem::RodModelProbe::step_checking_tangent(m);
            EXPECT_GE(err, 0.0) << "the check did not run";
            EXPECT_LT(err, 1e-6) << "at L = " << m.injected_length();
            ++checked;
          }
      }
    EXPECT_EQ(checked, 3) << "too few steps with wall and self contact";
  }

  TEST(RodModel, AssembledTangentIsTheDerivativeOfTheAssembledResidual)
  {
    // Elastoplastic wire with dashpots, friction, wall and self contact, in
    // generalized-alpha: check at steps with contacts.
    fem::RodModel m(
        fem_scene({"Wire/Plasticity/Yield curvature=0.05", "Contact/Friction/Static coefficient=0.5"}));
    check_tangent_in_contact(m, 45.0);
  }

  TEST(RodModel, DragTangentIsTheDerivativeAndItsWorkIsBookedAsDamping)
  {
    // FEM/Translational damping gamma: -gamma m v on the free nodes'
    // positions. The tangent with it is the derivative of the residual;
    // without dashpots the ledger's damping is the drag's work alone, and
    // the balance closes. Its rate is 2 gamma times the kinetic energy to
    // within the difference of the lumped mass (the drag's, on the free
    // positions) and the consistent one of the whole free wire with its
    // sections' rotation (the kinetic energy's): the ratio is 0.960, 0.968
    // and 0.971 at Step error 1e-2, 1e-3 and 1e-4, so 5% tells a wrong
    // factor from that.
    const double gamma = 0.5;
    fem::RodModel m(fem_scene({"Wire/Plasticity/Yield curvature=0.05", "FEM/Axial viscosity=0",
                               "FEM/Bending viscosity=0", "FEM/Translational damping=0.5"}));
    double expected = 0.0, t = m.time(), kinetic = m.energies().kinetic;
    while (m.injected_length() < 30.0)
      {
        m.step();
        expected += gamma * (kinetic + m.energies().kinetic) * (m.time() - t);
        t = m.time();
        kinetic = m.energies().kinetic;
      }
    const double booked = m.energies().damping;
    std::cout << "drag: booked " << booked << ", 2 gamma int E_k dt " << expected << "\n";
    EXPECT_GT(booked, 1.0);
    EXPECT_NEAR(booked / expected, 1.0, 0.05);
    EXPECT_LT(std::abs(m.energies().balance_error()), 5e-3);
    check_tangent_in_contact(m, 60.0);
  }

  TEST(RodModel, QuasiStaticTangentIsTheDerivativeOfTheResidualWithFrictionOnSlip)
  {
    // Quasi-static injection: friction reads the slip of a step over the
    // longest step (AssemblyRequest::friction_rate); the tangent must carry
    // that factor too.
    fem::RodModel m(contact_scene("FEM/Integrator=quasi-static"));
    check_tangent_in_contact(m, 60.0);
  }

  TEST(RodModel, ContactAlongTheElementTangentIsTheDerivativeOfTheResidual)
  {
    // FEM/Contact points: self and wall contact at Gauss points on the
    // curve of elements of degree 2, with friction (the wall's spring law)
    // and plasticity.
    fem::RodModel m(
        fem_scene({"Wire/Plasticity/Yield curvature=0.05", "Contact/Friction/Static coefficient=0.5",
                   "FEM/Degree=2", "FEM/Contact points=2"}));
    check_tangent_in_contact(m, 45.0);
  }

  TEST(RodModel, ContactAlongTheElementForceIsTheGradientOfItsEnergy)
  {
    // An elastic wire without friction: the assembled conservative forces
    // (dashpots apart) are the gradient of the stored energy, checked
    // at three states with self contact, for contact at the nodes (also
    // with twice the penalty between wires) and along elements of degree 1
    // and 3.
    for (const auto &keys : std::vector<std::vector<std::string>>{{"FEM/Contact points=0"},
                                                                  {"FEM/Self contact stiffness=2"},
                                                                  {"FEM/Contact points=2"},
                                                                  {"FEM/Degree=3", "FEM/Contact points=3"}})
      {
        auto o = keys;
        o.insert(o.end(), {"Wire/Plasticity/Enabled=false", "Contact/Friction/Static coefficient=0"});
        fem::RodModel m(fem_scene(o));
        int checked = 0;
        while (m.injected_length() < 45.0 && checked < 3)
          {
            m.step();
            if (m.report().n_self_contacts > 0 && m.n_steps() % 11 == 0)
              {
                EXPECT_LT(fem::RodModelProbe::force_gradient_error(m), 1e-6)
                    << keys.back() << " at L = " << m.injected_length();
                ++checked;
              }
          }
        EXPECT_EQ(checked, 3) << keys.back() << ": too few steps with self contact";
      }
  }

  TEST(RodModel, SelfContactStiffnessScalesTheWireOnWirePenaltyOnly)
  {
    // FEM/Self contact stiffness: the penalty between wires is that multiple
    // of k_n, the wall keeps k_n, and the fixed step's cap follows the
    // stiffer contact's period. (At 2 the assembled forces are the gradient
    // of the stored energy: ContactAlongTheElementForceIsTheGradientOfItsEnergy.)
    const auto stiffness = [](const std::vector<std::string> &keys) {
      return fem::RodModelProbe::contact_stiffness(fem::RodModel(fem_scene(keys)));
    };
    EXPECT_EQ(stiffness({}), std::make_pair(2000.0, 2000.0));
    EXPECT_EQ(stiffness({"FEM/Self contact stiffness=2"}), std::make_pair(2000.0, 4000.0));
    EXPECT_EQ(stiffness({"FEM/Self contact stiffness=0.5", "Contact/Normal stiffness=1000"}),
              std::make_pair(1000.0, 500.0));
    const auto cap = [](const std::string &factor) {
      return fem::RodModelProbe::step_cap(
          fem::RodModel(fem_scene({"FEM/Step error=0", "FEM/Self contact stiffness=" + factor})));
    };
    EXPECT_DOUBLE_EQ(cap("0.5"), 0.025); // the wall's period: 0.028
    EXPECT_DOUBLE_EQ(cap("4"), 0.4 * M_PI * std::sqrt(1.0 / 8000.0));
  }

  TEST(RodModel, ContactAlongTheElementKeepsTheWallOutOfTheChannels)
  {
    // Tangential channels lie along the wall: contact points on a segment
    // reaching into a channel pressed the wall there, and the ledger,
    // which books the channel's reactions as its work, ended 19% off here
    // (1.9% on the classic scene at f = 10). The points act on the segments
    // between the wall's nodes.
    // Newton at 1e-8 of EA: the remainder of this short, impact-heavy run
    // moves with its trajectory, 1.2e-3 to 5.1e-3 under tolerances 1e-8,
    // 1e-7, 1e-6 and 3e-6 (in no order of the tolerance), so the limit
    // holds one trajectory; the fault it guards against left 19%.
    fem::RodModel m(fem_scene({"Cavity/Radius=10", "Injection/Channels=tangential", "FEM/Contact points=2",
                               "FEM/Newton tolerance=1e-8"}));
    while (m.injected_length() < 60.0)
      m.step();
    EXPECT_LT(std::abs(m.energies().balance_error()), 5e-3);
  }

  TEST(RodModel, AKirchhoffRodStartsWithoutSpuriousShearEnergy)
  {
    // The continuum case's scene (validation/continuum/injection.prm) at
    // h = d: the section angles of the seeded start, taken from the curve's
    // tangent, gave the shear penalty an energy of 574 against a bending
    // energy of a few units; it was lost in the first steps and the ledger
    // ended 83% off. The start now relaxes the angles.
    fem::RodModel m(scene::read_scene(
        "", {"Model=fem", "FEM/Formulation=kirchhoff", "Cavity/Radius=10", "Wire/Axial stiffness=1000",
             "Wire/Bending stiffness=60", "Wire/Mass per length=1", "Wire/Plasticity/Enabled=false",
             "Contact/Friction/Static coefficient=0", "Injection/Speed=0.1", "Injection/Ramp time=20",
             "Discrete/Axial damping=3", "Discrete/Rotational damping=0.5", "Output/Progress=off"}));
    EXPECT_LT(m.energies().initial, 10.0);
    while (m.injected_length() < 22.0)
      m.step();
    EXPECT_LT(std::abs(m.energies().balance_error()), 1e-2);
  }

  TEST(RodModel, QuasiStaticInjectionKeepsItsStartShapeAndCostsTheSameAtAnySpeed)
  {
    // Without inertia the start's perturbation is stress-free (its bending
    // energy is a hundredth of the dynamic start's or less, and the wire
    // stays bent as it is pushed), friction
    // acts on the slip per step, and the steps go by injected length: the
    // runs at speeds 1 and 0.1 take about the same steps (implicit dynamics
    // takes 10 times as many at 0.1) and both get past their first self
    // contacts to phi 0.3 with the ledger closed to 1% (the start shape's
    // stretch relaxed before the ledger opens).
    unsigned long steps[2] = {0, 0};
    int k = 0;
    for (const char *speed : {"Injection/Speed=1", "Injection/Speed=0.1"})
      {
        const std::vector<std::string> keys{"Wire/Plasticity/Yield curvature=0.05",
                                            "Contact/Friction/Static coefficient=0.5", speed};
        auto qs_keys = keys;
        qs_keys.push_back("FEM/Integrator=quasi-static");
        fem::RodModel m(fem_scene(qs_keys));
        // The dynamic start holds the perturbation's bending energy.
        const fem::RodModel dynamic(fem_scene(keys));
        EXPECT_LT(m.energies().bending, 0.01 * dynamic.energies().initial) << speed;
        bool bent = false, touched = false;
        const double start = m.injected_length();
        while (analysis::packing_density(m.injected_length(), 6.0) < 0.3)
          {
            m.step();
            bent = bent || (m.injected_length() < start + 1.0 && m.energies().bending > 1e-3);
            touched = touched || m.report().n_self_contacts > 0;
          }
        EXPECT_TRUE(bent) << speed << ": the start shape did not persist";
        EXPECT_TRUE(touched) << speed;
        EXPECT_LT(std::abs(m.energies().balance_error()), 0.01) << speed;
        steps[k++] = m.n_steps();
      }
    EXPECT_LT(static_cast<double>(steps[1]), 1.5 * static_cast<double>(steps[0]))
        << steps[0] << " steps at speed 1, " << steps[1] << " at 0.1";
    EXPECT_GT(static_cast<double>(steps[1]), static_cast<double>(steps[0]) / 1.5);
  }

  TEST(RodModel, QuasiStaticLedgerClosesAtSecondOrderUnderStrongWallFriction)
  {
    // Both ends of a quasi-static step are equilibria, so the work of the
    // forces booked by the trapezoidal rule closes the ledger to second
    // order in the step. Booked with the end forces alone it closed at
    // first order, to 9.6e-2 at the middle step here (mu_st 5 on the wall).
    double error[3] = {0, 0, 0};
    int k = 0;
    for (const char *step : {"FEM/Time step=0.16667", "FEM/Time step=0.083333", "FEM/Time step=0.041667"})
      {
        fem::RodModel m(fem_scene({"Cavity/Radius=10", "Wire/Plasticity/Yield curvature=0.04",
                                   "Wire/Plasticity/Hardening slope=0.08",
                                   "Contact/Friction/Static coefficient=5", "Injection/Speed=0.3",
                                   "Injection/Ramp time=10", "FEM/Integrator=quasi-static", step}));
        while (analysis::packing_density(m.injected_length(), 10.0) < 0.2)
          m.step();
        ASSERT_GT(m.report().n_wall_contacts, 0) << step;
        error[k++] = std::abs(m.energies().balance_error());
      }
    EXPECT_LT(error[1], 2e-3) << error[1];
    // Order >= 1.5 between each pair of steps.
    EXPECT_GT(error[0] / error[1], 2.8) << error[0] << " " << error[1];
    EXPECT_GT(error[1] / error[2], 2.8) << error[1] << " " << error[2];
  }

  scene::Scene snapping_scene()
  {
    // At mu_st 5 and friction's creep 0.01 per length injected (v_th over
    // the speed) the quasi-static wire meets a state with no equilibrium
    // near (Newton fails down to the smallest step) at L = 33.9.
    return fem_scene({"Wire/Plasticity/Yield curvature=0.05", "Contact/Friction/Static coefficient=5",
                      "FEM/Integrator=quasi-static", "FEM/Quasi-static creep=0.01"});
  }

  TEST(RodModel, QuasiStaticInjectionHandsASnapToDynamicsAndGoesOn)
  {
    // The snap is taken by generalized-alpha with the injection paused
    // (the injected length does not move), and quasi-static stepping
    // resumes once the wire is calm; the run gets to phi 0.5.
    fem::RodModel m(snapping_scene());
    bool paused_held = true, resumed = false;
    while (analysis::packing_density(m.injected_length(), 6.0) < 0.5)
      {
        const double before = m.injected_length();
        const bool dynamic = fem::RodModelProbe::in_dynamic_phase(m);
        m.step();
        if (dynamic && fem::RodModelProbe::in_dynamic_phase(m))
          paused_held = paused_held && m.injected_length() == before;
        resumed = resumed || (dynamic && !fem::RodModelProbe::in_dynamic_phase(m));
      }
    EXPECT_GE(fem::RodModelProbe::snaps(m), 1u);
    EXPECT_TRUE(paused_held) << "the injection moved in a dynamic phase";
    EXPECT_TRUE(resumed) << "never back to quasi-static steps";
  }

  TEST(RodModel, QuasiStaticStepsHaveDashpotsOnlyWhenAsked)
  {
    // FEM/Quasi-static dashpots: whether the dashpots act in quasi-static
    // steps (rates over the injection's time). Their work up to the first
    // snap (or phi 0.5): some with them, none without; the ledger closes
    // either way.
    for (const bool dashpots : {true, false})
      {
        auto s = snapping_scene();
        s.fem.quasi_static_dashpots = dashpots;
        fem::RodModel m(s);
        double damping = 0, balance = 0;
        while (fem::RodModelProbe::snaps(m) == 0 && analysis::packing_density(m.injected_length(), 6.0) < 0.5)
          {
            damping = m.energies().damping;
            balance = m.energies().balance_error();
            m.step();
          }
        ASSERT_GT(m.n_steps(), 100u) << dashpots;
        if (dashpots)
          EXPECT_GT(damping, 1e-4 * m.energies().in()) << damping;
        else
          EXPECT_EQ(damping, 0.0);
        EXPECT_LT(std::abs(balance), 0.01) << dashpots;
      }
    // Generalized-alpha keeps its dashpots whatever the flag says.
    fem::RodModel dynamic(fem_scene({"FEM/Quasi-static dashpots=false"}));
    while (dynamic.injected_length() < 20.0)
      dynamic.step();
    EXPECT_GT(dynamic.energies().damping, 0.0);
  }

  TEST(RodModel, WithoutQuasiStaticDashpotsTheSnapsFollowTheStepError)
  {
    // Without dashpots in its steps the elastic wire at mu_st 5 snaps
    // often, and the snaps' generalized-alpha steps follow FEM/Step error
    // (not the fixed step of snaps with dashpots): steps longer than the
    // fixed one, or made again for their error.
    fem::RodModel m(scene::read_scene(
        "", {"Model=fem", "Cavity/Radius=8", "Output/Progress=off", "Wire/Plasticity/Enabled=false",
             "Contact/Friction/Static coefficient=5", "Injection/Speed=0.3", "FEM/Integrator=quasi-static",
             "FEM/Quasi-static dashpots=false"}));
    double longest = 0;
    unsigned long dynamic_steps = 0;
    while (fem::RodModelProbe::snaps(m) < 3 && analysis::packing_density(m.injected_length(), 8.0) < 0.5)
      {
        const bool dynamic = fem::RodModelProbe::in_dynamic_phase(m);
        const double before = m.time();
        m.step();
        if (dynamic && fem::RodModelProbe::in_dynamic_phase(m))
          {
            longest = std::max(longest, m.time() - before);
            ++dynamic_steps;
          }
      }
    ASSERT_GE(fem::RodModelProbe::snaps(m), 3u);
    ASSERT_GT(dynamic_steps, 20u);
    EXPECT_GT(longest, 1.5 * 0.025) << "the snaps kept the fixed step";
    EXPECT_LT(std::abs(m.energies().balance_error()), 0.01);
  }

  TEST(RodModel, QuasiStaticFrictionCreepsPerInjectedLengthNotPerTime)
  {
    // Quasi-static steps go by injected length; their friction creeps by
    // FEM/Quasi-static creep per length injected. Without dashpots in
    // those steps (their rates are over the injection's time), runs at
    // speeds 1 and 0.1 are then the same run. With the creep 0 (the
    // dynamic law's, v_th / speed) they are not.
    auto run = [](const std::string &speed, const std::string &creep) {
      std::vector<std::string> keys{speed,
                                    "Injection/Ramp time=0",
                                    "FEM/Integrator=quasi-static",
                                    "FEM/Quasi-static dashpots=false",
                                    "Contact/Friction/Static coefficient=0.5",
                                    "FEM/Quasi-static creep=" + creep};
      fem::RodModel m(fem_scene(keys));
      bool touched = false;
      while (analysis::packing_density(m.injected_length(), 6.0) < 0.3)
        {
          m.step();
          touched = touched || m.report().n_self_contacts > 0;
        }
      EXPECT_TRUE(touched) << speed;
      EXPECT_EQ(fem::RodModelProbe::snaps(m), 0u) << speed;
      return std::pair{m.n_steps(), m.energies().bending + m.energies().friction};
    };
    const auto fast = run("Injection/Speed=1", "0.04"), slow = run("Injection/Speed=0.1", "0.04");
    EXPECT_EQ(fast.first, slow.first);
    EXPECT_NEAR(slow.second / fast.second, 1.0, 1e-9) << fast.second << " " << slow.second;
    const auto fast0 = run("Injection/Speed=1", "0"), slow0 = run("Injection/Speed=0.1", "0");
    EXPECT_GT(std::abs(slow0.second / fast0.second - 1.0), 1e-3) << fast0.second << " " << slow0.second;
    // The creep the dynamic law has at speed 1 (v_th 0.01 over 1): the
    // same law, so the same run (up to rounding in the rate).
    const auto same = run("Injection/Speed=1", "0.01");
    EXPECT_EQ(same.first, fast0.first);
    EXPECT_NEAR(same.second / fast0.second, 1.0, 1e-6) << same.second << " " << fast0.second;
    // And the creep matters: ten times as much lets the contacts slip.
    const auto loose = run("Injection/Speed=1", "0.4");
    EXPECT_GT(std::abs(loose.second / fast.second - 1.0), 1e-3) << loose.second << " " << fast.second;
  }

  TEST(RodModel, QuasiStaticStepsThatMissEnergyAreMadeShorter)
  {
    // prm/classic.prm at f = 10 with no yield moment: the straight wire is
    // pushed in compressed and buckles within a few quasi-static steps that
    // the dashpots hold back; booked by the trapezoidal rule those steps
    // leave about 2% of the energy put in out of the ledger. FEM/Quasi-static
    // energy error makes a step whose own imbalance is over four times its
    // share again, shorter, and the ledger closes.
    auto run = [](const std::string &energy) {
      fem::RodModel m(scene::read_scene(WIREFEM_SOURCE_DIR "/prm/classic.prm",
                                        {"Model=fem", "Cavity/Radius=10", "Output/Progress=off",
                                         "Wire/Plasticity/Yield curvature=0", "FEM/Integrator=quasi-static",
                                         "FEM/Quasi-static energy error=" + energy}));
      while (analysis::packing_density(m.injected_length(), 10.0) < 0.3)
        m.step();
      EXPECT_EQ(fem::RodModelProbe::snaps(m), 0u) << energy;
      return m.energies().balance_error();
    };
    EXPECT_GT(std::abs(run("0")), 0.01);
    EXPECT_LT(std::abs(run("0.1")), 0.01);
  }

  TEST(RodModel, QuasiStaticSnapsIgnoreTheStepError)
  {
    // FEM/Step error acts on generalized-alpha runs only: a quasi-static
    // run through a snap is the same run, bit for bit, whatever it says.
    auto with_control = snapping_scene();
    with_control.fem.step_error = 1e-3;
    auto fixed = snapping_scene();
    fixed.fem.step_error = 0.0;
    fem::RodModel a(with_control), b(fixed);
    while (analysis::packing_density(a.injected_length(), 6.0) < 0.5)
      {
        a.step();
        b.step();
        ASSERT_EQ(a.time(), b.time()) << "step " << a.n_steps();
      }
    EXPECT_GE(fem::RodModelProbe::snaps(a), 1u);
    EXPECT_EQ(largest_distance(a, b), 0.0);
  }

  TEST(RodModel, ASnapWhereTheLastOneWasPushesOnBeforeItPauses)
  {
    // A snap that comes back where the last one was first injects
    // qs_push (0.25 d per channel) at the scene's speed, then holds the
    // channels until the wire is calm, and quasi-static steps go on.
    fem::RodModel m(snapping_scene());
    while (m.injected_length() < 20.0)
      m.step();
    ASSERT_FALSE(fem::RodModelProbe::in_dynamic_phase(m));
    const double start = m.injected_length();
    fem::RodModelProbe::snap_again(m);
    EXPECT_EQ(fem::RodModelProbe::pushes(m), 1u);
    double pushed = start;
    const double cap = fem::RodModelProbe::step_cap(m); // the dynamic phase's longest step
    bool held = true, paused = false;
    while (fem::RodModelProbe::in_dynamic_phase(m))
      {
        const double before = m.injected_length();
        m.step();
        if (paused && fem::RodModelProbe::in_dynamic_phase(m))
          held = held && m.injected_length() == before;
        if (!paused && m.injected_length() == before)
          paused = true;
        pushed = std::max(pushed, m.injected_length());
      }
    // Two channels, 0.25 d each, reached within one dynamic step (speed 1).
    EXPECT_GE(pushed - start, 0.5);
    EXPECT_LE(pushed - start, 0.5 + 2.0 * cap + 1e-9);
    EXPECT_TRUE(paused);
    EXPECT_TRUE(held) << "the injection moved after the push";
    const double back = m.injected_length();
    m.step();
    EXPECT_GT(m.injected_length(), back) << "no quasi-static step after the phase";
  }

  TEST(RodModel, APushingPhaseSavesAndLoadsBitForBit)
  {
    const auto s = snapping_scene();
    fem::RodModel straight(s), resumed(s);
    while (straight.injected_length() < 20.0)
      straight.step();
    fem::RodModelProbe::snap_again(straight);
    for (int i = 0; i < 4; ++i)
      straight.step();
    std::stringstream buffer;
    straight.save(buffer);
    resumed.load(buffer);
    for (int i = 0; i < 300; ++i)
      {
        straight.step();
        resumed.step();
      }
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(straight.injected_length(), resumed.injected_length());
    EXPECT_GT(straight.injected_length(), 20.5);
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
    EXPECT_EQ(straight.energies().kinetic, resumed.energies().kinetic);
  }

  TEST(RodModel, ADynamicPhaseSavesAndLoadsBitForBit)
  {
    const auto s = snapping_scene();
    fem::RodModel straight(s), first(s), resumed(s);
    while (!fem::RodModelProbe::in_dynamic_phase(first))
      first.step();
    for (int i = 0; i < 100; ++i)
      first.step();
    ASSERT_TRUE(fem::RodModelProbe::in_dynamic_phase(first));
    std::stringstream buffer;
    first.save(buffer);
    resumed.load(buffer);
    while (straight.n_steps() < first.n_steps())
      straight.step();
    for (int i = 0; i < 300; ++i)
      {
        straight.step();
        resumed.step();
      }
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
    EXPECT_EQ(fem::RodModelProbe::in_dynamic_phase(straight), fem::RodModelProbe::in_dynamic_phase(resumed));
    EXPECT_EQ(straight.energies().kinetic, resumed.energies().kinetic);
  }

  TEST(RodModel, ThePatternHoldsThePairsNearContactAndAPairThatComesNear)
  {
    // K's pattern holds the candidate pairs near contact, fewer than the
    // broad phase's. A Newton iterate that brings another pair into contact
    // widens it, and the tangent there is still the derivative of the
    // residual.
    fem::RodModel m(
        fem_scene({"Wire/Plasticity/Yield curvature=0.05", "Contact/Friction/Static coefficient=0.5"}));
    while (m.injected_length() < 40.0)
      m.step();
    const auto r = fem::RodModelProbe::step_pushing_a_pair_into_contact(m);
    ASSERT_TRUE(r.found) << "every candidate pair was in the pattern";
    EXPECT_GT(r.pattern_pairs, 0u);
    EXPECT_LT(r.pattern_pairs, r.candidates);
    EXPECT_TRUE(r.touching);
    EXPECT_TRUE(r.in_pattern_after);
    EXPECT_GE(r.tangent_error, 0.0);
    EXPECT_LT(r.tangent_error, 1e-6);
  }

  TEST(RodModel, KeptFactorsFollowTheRefactorisedRunAndFactoriseLess)
  {
    // The same elastoplastic run with friction, wall and self contact, once
    // with an LU of every tangent and once with GMRES on kept factors. Each
    // GMRES solve reaches 1e-9 of Newton's residual (or 1e-3 of its
    // tolerance), so both runs take the same steps and their wires agree to
    // far less than the contact overlaps; GMRES factorises a fraction as
    // often (68 against 1,187 times here).
    fem::RodModel lu(contact_scene("FEM/Linear solver=refactorise"));
    fem::RodModel kept(contact_scene("FEM/Linear solver=kept factors"));
    const double worst = in_step(lu, kept, 30.0);
    EXPECT_GT(lu.report().n_self_contacts + lu.report().n_wall_contacts, 0);
    // GMRES leaves 1e-3 of the Newton tolerance (1e-8 EA) in the residual:
    // the wires differ by about 1e-9 d (4e-7 d with a floor of 0.5); a
    // solve off by a step's motion (0.025 d) or a different trajectory
    // would show at 1e-7.
    EXPECT_LT(worst, 1e-7) << "largest distance between the two wires (d)";
    const auto &s_lu = fem::RodModelProbe::linear_statistics(lu);
    const auto &s_kept = fem::RodModelProbe::linear_statistics(kept);
    EXPECT_EQ(s_lu.kept_solves, 0u);
    EXPECT_GT(s_kept.kept_solves, 0u);
    const auto factorised = [](const auto &s) { return s.factorisations + s.refactorisations; };
    EXPECT_LT(factorised(s_kept), factorised(s_lu) / 3) << s_kept.kept_iterations << " GMRES iterations";
    std::cout << "largest distance " << worst << " d; factorisations " << factorised(s_lu) << " against "
              << factorised(s_kept) << " with " << s_kept.kept_iterations << " GMRES iterations in "
              << s_kept.kept_solves << " solves\n";
  }

  TEST(RodModel, TheBandSolverFollowsTheRefactorisedRunWithoutFactorisingTheTangent)
  {
    // The run of the test above once more with GMRES on the LU of the
    // tangent's band (each node with its neighbours; the contacts between
    // distant stretches left to GMRES). Solved to 1e-9 of Newton's
    // residual, it takes the same steps as the run with an LU of every
    // tangent, and the wires agree to far less than the contact overlaps,
    // while the whole tangent is factorised only where the run starts.
    fem::RodModel lu(contact_scene("FEM/Linear solver=refactorise"));
    fem::RodModel band(contact_scene("FEM/Linear solver=band", "FEM/Linear tolerance=1e-9"));
    const double worst = in_step(lu, band, 30.0);
    EXPECT_GT(lu.report().n_self_contacts, 0);
    EXPECT_LT(worst, 1e-7) << "largest distance between the two wires (d)";
    const auto &s_lu = fem::RodModelProbe::linear_statistics(lu);
    const auto &s_band = fem::RodModelProbe::linear_statistics(band);
    EXPECT_EQ(s_lu.band_solves, 0u);
    EXPECT_GT(s_band.band_solves, 1000u);
    EXPECT_EQ(s_band.band_refactorised, 0u);
    EXPECT_EQ(fem::RodModelProbe::retried_steps(band), 0u);
    const auto factorised = [](const auto &s) { return s.factorisations + s.refactorisations; };
    EXPECT_LT(factorised(s_band), 10u) << "the start's direct solves only";
    std::cout << "largest distance " << worst << " d; " << s_band.band_iterations << " GMRES iterations in "
              << s_band.band_solves << " solves\n";
  }

  TEST(RodModel, TheAutomaticLinearSolverIsTheBandWithGeneralizedAlpha)
  {
    // With generalized-alpha, Linear solver = auto is the band: the same
    // run bit for bit, its solves by GMRES on the band's LU.
    fem::RodModel band(contact_scene("FEM/Linear solver=band"));
    fem::RodModel automatic(contact_scene("FEM/Linear solver=auto"));
    EXPECT_EQ(in_step(band, automatic, 30.0), 0.0);
    EXPECT_GT(fem::RodModelProbe::linear_statistics(automatic).band_solves, 100u);
  }

  TEST(RodModel, QuasiStaticStepsRefactoriseWithTheBandSolver)
  {
    // Without the mass term the band is a poor preconditioner: quasi-static
    // steps refactorise whatever FEM/Linear solver says (auto as well).
    for (const char *solver : {"FEM/Linear solver=band", "FEM/Linear solver=auto"})
      {
        fem::RodModel m(fem_scene({"FEM/Integrator=quasi-static", solver}));
        while (m.injected_length() < 30.0)
          m.step();
        EXPECT_EQ(fem::RodModelProbe::linear_statistics(m).band_solves, 0u) << solver;
        EXPECT_GT(fem::RodModelProbe::linear_statistics(m).refactorisations, 100u) << solver;
      }
  }

  TEST(RodModel, ModifiedNewtonReachesTheSameWireWithFewerFactorisations)
  {
    // Modified Newton reuses each step's first LU while the residual
    // contracts tenfold per iteration; each run converges to the Newton
    // tolerance (1e-8 EA), so wherever both reach the same time their wires
    // agree far below a step's motion (0.025 d), and the modified run
    // factorises less than once per iteration.
    fem::RodModel full(contact_scene("FEM/Newton=full", "FEM/Linear solver=refactorise"));
    fem::RodModel modified(contact_scene("FEM/Newton=modified"));
    const double worst = at_equal_times(full, modified, 30.0);
    // Each converged state is within the Newton tolerance (1e-5 in force)
    // of the exact one, about 1e-8 d through the step's mass term, and such
    // differences are carried from step to step (here up to 4e-6 d); a
    // wrong step (a step's motion is 0.025 d) or another trajectory would
    // show at 1e-3.
    EXPECT_LT(worst, 1e-5) << "largest distance between the two wires (d)";
    const auto factorised = [](const auto &s) { return s.factorisations + s.refactorisations; };
    const auto &s_full = fem::RodModelProbe::linear_statistics(full);
    const auto &s_mod = fem::RodModelProbe::linear_statistics(modified);
    EXPECT_LT(factorised(s_mod), 0.7 * fem::RodModelProbe::newton_iterations(modified));
    EXPECT_LT(factorised(s_mod), factorised(s_full));
    std::cout << "largest distance " << worst << " d; factorisations " << factorised(s_full) << " in "
              << fem::RodModelProbe::newton_iterations(full) << " iterations against " << factorised(s_mod)
              << " in " << fem::RodModelProbe::newton_iterations(modified) << "\n";
  }

  TEST(RodModel, ModifiedNewtonThatAcceptsNoContractionIsFullNewtonBitForBit)
  {
    // With a contraction no iteration reaches, every iteration of modified
    // Newton assembles the tangent where full Newton does, from the same
    // state: the two runs are the same run, bit for bit. (This tests the
    // fall-back to a tangent after a slow iteration, and the line search
    // after a fresh tangent; no solve reuses factors here.)
    fem::RodModel full(contact_scene("FEM/Newton=full", "FEM/Linear solver=refactorise"));
    auto sc = contact_scene("FEM/Newton=modified");
    sc.fem.newton_contraction = 1e-300;
    fem::RodModel modified(sc);
    while (full.injected_length() < 20.0)
      {
        full.step();
        modified.step();
        ASSERT_EQ(full.time(), modified.time()) << "step " << full.n_steps();
      }
    EXPECT_EQ(largest_distance(full, modified), 0.0);
    EXPECT_EQ(fem::RodModelProbe::newton_iterations(full), fem::RodModelProbe::newton_iterations(modified));
  }

  TEST(RodModel, TheVelocityPredictorReachesTheSameWireInFewerIterations)
  {
    // The predictor is only Newton's first guess: both runs converge to
    // the same states wherever they reach the same time (each to the
    // Newton tolerance, 1e-8 EA), and the constant-velocity guess, which
    // does not extrapolate the short-lived accelerations of contact
    // events, needs fewer iterations under the regularised law between
    // wires. (With the springs between wires, the default, the two are
    // within 1% here; on the classic scene the constant-velocity guess
    // still needs 5% fewer per injected length:
    // docs/notes/2026-12-06-fem-defaults.md.)
    fem::RodModel acc(
        contact_scene("FEM/Predictor=constant acceleration", "FEM/Self friction law=regularised"));
    fem::RodModel vel(contact_scene("FEM/Predictor=constant velocity", "FEM/Self friction law=regularised"));
    const double worst = at_equal_times(acc, vel, 30.0);
    // A wrong predictor term in the converged state (a step's motion is
    // 0.025 d) or a different trajectory would show at 1e-6.
    EXPECT_LT(worst, 1e-6) << "largest distance between the two wires (d)";
    const auto its_acc = fem::RodModelProbe::newton_iterations(acc);
    const auto its_vel = fem::RodModelProbe::newton_iterations(vel);
    EXPECT_LT(its_vel, its_acc) << "Newton iterations, those of cut steps included";
    std::cout << "largest distance " << worst << " d; Newton iterations " << its_acc << " against " << its_vel
              << "\n";
  }

  TEST(RodModel, OverlapGrowthCutsTheStepsThatCrossAnImpact)
  {
    // The largest growth of the largest overlap within one step, over the
    // steps longer than 1/16 of the cap (the control's floor), with and
    // without FEM/Overlap growth; the same run otherwise.
    const double limit = 0.004;
    const auto run = [](const std::string &growth) {
      // Fixed steps: the control halves a step of the cap down to 1/16 of
      // it, and the error control's steps lie in between.
      fem::RodModel m(fem_scene(
          {"Wire/Plasticity/Yield curvature=0.05", "FEM/Step error=0", "FEM/Overlap growth=" + growth}));
      const double floor = fem::RodModelProbe::step_cap(m) / 16;
      double before = 0.0, worst = 0.0;
      while (m.injected_length() < 30.0)
        {
          const double t0 = m.time();
          m.step();
          const double overlap = m.report().max_penetration;
          if (m.time() - t0 > floor * (1 + 1e-12))
            worst = std::max(worst, overlap - before);
          before = overlap;
        }
      return std::make_pair(worst, fem::RodModelProbe::overlap_cuts(m));
    };
    const auto [free_growth, free_cuts] = run("0");
    const auto [growth, cuts] = run(std::to_string(limit));
    EXPECT_EQ(free_cuts, 0u);
    EXPECT_GT(free_growth, 2 * limit) << "no impact in the run to test the control on";
    EXPECT_LE(growth, limit);
    EXPECT_GT(cuts, 0u);
    std::cout << "largest overlap growth in a step: " << free_growth << " d without the control, " << growth
              << " d with " << limit << " d (" << cuts << " steps cut)\n";
  }

  TEST(RodModel, StepErrorEstimateIsThirdOrderInTheStep)
  {
    // From the start of a run (a smooth state), one step of h, h/2, h/4
    // and h/8: the estimate h^2 |beta - 1/6| max |a_{n+1} - a_n| is the
    // leading term of a local error of order 3 in h. (Targets 1e9:
    // estimated, never acted on. Later in a run with contacts the estimate
    // is of order 2: contacts keep an alternating part in the
    // accelerations, docs/notes/2026-12-06-step-energy-error.md.)
    auto s = contact_scene("FEM/Step error=1e9");
    s.fem.step_energy_error = 1e9;
    fem::RodModel m(s);
    std::stringstream saved;
    m.save(saved);
    std::vector<double> estimate;
    for (const double h : {0.016, 0.008, 0.004, 0.002})
      {
        fem::RodModel r(s);
        saved.clear();
        saved.seekg(0);
        r.load(saved);
        fem::RodModelProbe::set_next_step(r, h);
        const double t0 = r.time();
        r.step();
        ASSERT_NEAR(r.time() - t0, h, 1e-12 * h) << "the step was cut";
        estimate.push_back(fem::RodModelProbe::error_estimate(r));
      }
    for (std::size_t i = 1; i < estimate.size(); ++i)
      {
        const double order = std::log2(estimate[i - 1] / estimate[i]);
        std::cout << "estimate " << estimate[i] << " d, order " << order << "\n";
        EXPECT_NEAR(order, 3.0, 0.3);
      }
  }

  TEST(RodModel, StepEnergyEstimateOverTwoStepsFallsWithTheStep)
  {
    // From a state of a run with wall contact and friction (made with steps
    // of 0.001), two steps of h: the ledger's imbalance over both, over
    // their share of the energy in, falls as h does. (Over one step it need
    // not: generalized-alpha's alternating part. Both targets 1e9:
    // estimated, never acted on.)
    auto s = contact_scene("FEM/Step error=1e9");
    s.fem.step_energy_error = 1e9;
    s.fem.time_step = 0.001;
    fem::RodModel m(s);
    while (m.injected_length() < 20.0)
      m.step();
    ASSERT_GT(m.report().n_wall_contacts, 0);
    std::stringstream saved;
    m.save(saved);
    std::vector<double> two, one;
    for (const double h : {0.016, 0.008, 0.004, 0.002, 0.001})
      {
        fem::RodModel r(s);
        saved.clear();
        saved.seekg(0);
        r.load(saved);
        fem::RodModelProbe::set_next_step(r, h);
        r.step();
        one.push_back(fem::RodModelProbe::energy_estimate(r));
        fem::RodModelProbe::set_next_step(r, h);
        r.step();
        two.push_back(fem::RodModelProbe::energy_estimate(r));
        std::cout << "h " << h << ": energy estimate over one step " << one.back() << ", over two "
                  << two.back() << "\n";
      }
    for (std::size_t i = 1; i < two.size(); ++i)
      EXPECT_LT(two[i], two[i - 1]);
    EXPECT_LT(two.back(), 0.5 * two.front());
  }

  TEST(RodModel, StepEnergyErrorKeepsTheLedgerWithStiffContacts)
  {
    // Ten times the contact stiffness and FEM/Step error: steps longer than
    // a contact's period, in which impacts make energy the local error does
    // not see. The energy estimate (the default target) shortens them, and
    // the ledger closes.
    double balance[2];
    unsigned long steps[2];
    for (const bool energy : {false, true})
      {
        auto s = contact_scene("FEM/Step error=1e-2");
        s.contact.normal_stiffness *= 10;
        if (!energy)
          s.fem.step_energy_error = 0;
        fem::RodModel m(s);
        while (m.injected_length() < 40.0)
          m.step();
        balance[energy] = m.energies().balance_error();
        steps[energy] = m.n_steps();
        std::cout << (energy ? "with" : "without") << " the energy estimate: " << m.n_steps()
                  << " steps, balance error " << balance[energy] << "\n";
      }
    EXPECT_GT(std::abs(balance[0]), 1e-2) << "no energy made by the long steps, nothing to test";
    EXPECT_LT(std::abs(balance[1]), 5e-3);
    EXPECT_GT(steps[1], steps[0]);
  }

  TEST(RodModel, StepErrorSetsTheStepsFromTheEstimate)
  {
    // With FEM/Step error the steps grow past the fixed cap where the
    // wire moves smoothly and shrink where contacts start; every step
    // above the control's floor (1/64 of its cap) is accepted within four
    // times the target, and some are made again.
    const double target = 1e-3;
    fem::RodModel m(contact_scene("FEM/Step error=" + std::to_string(target)));
    const double fixed_cap = 0.025, floor = fem::RodModelProbe::step_cap(m) / 64;
    double shortest = INFINITY, longest = 0.0, worst = 0.0;
    while (m.injected_length() < 30.0)
      {
        const double t0 = m.time();
        m.step();
        const double step = m.time() - t0;
        shortest = std::min(shortest, step);
        longest = std::max(longest, step);
        if (step > floor * (1 + 1e-12))
          worst = std::max(worst, fem::RodModelProbe::error_estimate(m));
      }
    EXPECT_GT(longest, 2 * fixed_cap);
    EXPECT_LT(shortest, fixed_cap);
    EXPECT_LE(worst, 4 * target);
    EXPECT_GT(fem::RodModelProbe::error_cuts(m), 0u);
    std::cout << m.n_steps() << " steps of " << shortest << " to " << longest << ", "
              << fem::RodModelProbe::error_cuts(m) << " made again; largest accepted estimate " << worst
              << " d\n";
  }

  TEST(RodModel, StepErrorSavesAndLoadsBitForBit)
  {
    // The next step's length is in the checkpoint, and so are the steps
    // made again.
    const auto s = contact_scene("FEM/Step error=1e-4");
    fem::RodModel straight(s), first(s), resumed(s);
    checks::run_straight_and_resumed(straight, first, resumed, 20.0, 30.0);
    EXPECT_GT(fem::RodModelProbe::error_cuts(straight), fem::RodModelProbe::error_cuts(first))
        << "no step made again after the checkpoint";
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(fem::RodModelProbe::error_cuts(straight), fem::RodModelProbe::error_cuts(resumed));
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
  }

  TEST(RodModel, SaveAndLoadContinueBitForBit)
  {
    // With the overlap-growth cut on, whose test reads the last step's
    // largest overlap: that is part of the checkpoint too, as is K's
    // sparsity pattern (rebuilt from the pairs near contact at load, the
    // run continues 1e-13 d off). Saved where the wire is dense.
    const auto s = contact_scene("FEM/Overlap growth=0.004");
    fem::RodModel straight(s), first(s), resumed(s);
    checks::run_straight_and_resumed(straight, first, resumed, 38.0, 45.0);
    EXPECT_GT(fem::RodModelProbe::overlap_cuts(straight), fem::RodModelProbe::overlap_cuts(first))
        << "no step cut for overlap growth after the checkpoint";
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(fem::RodModelProbe::overlap_cuts(straight), fem::RodModelProbe::overlap_cuts(resumed));
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
  }

  TEST(RodModel, ContactAlongTheElementSavesAndLoadsBitForBit)
  {
    // The wall springs of the contact points are part of the checkpoint.
    const auto s =
        fem_scene({"Contact/Friction/Static coefficient=0.5", "FEM/Degree=2", "FEM/Contact points=2"});
    fem::RodModel straight(s), first(s), resumed(s);
    checks::run_straight_and_resumed(straight, first, resumed, 38.0, 45.0);
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
  }

  TEST(RodModel, OneChannelLeavesTheWiresEndFreeAndResumesBitForBit)
  {
    // The mesh ends at the free end: the wire state's last point is the
    // last node, in the cavity, at arc length L = L0 + u.
    const auto s = contact_scene("Injection/Channel positions=0.5");
    fem::RodModel straight(s), first(s), resumed(s);
    checks::run_straight_and_resumed(straight, first, resumed, 20.0, 30.0);
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
    const auto w = straight.wire_state();
    EXPECT_NEAR(core::norm(w.points.front() - core::Vec2{-6.0, 0.0}), 0.0, 1e-12);
    EXPECT_LT(core::norm(w.points.back()), 6.0 - 0.45);
    EXPECT_NEAR(w.arc_length.back(), straight.injected_length(), 1e-9);
    EXPECT_EQ(straight.force_right(), 0.0);
    EXPECT_GT(straight.force_left(), 0.0);
  }

  TEST(RodModel, OneChannelsFreeTipPressesTheWireAndItsTangentIsTheDerivative)
  {
    // The free tip (the last node, which begins no segment) presses the
    // wire it meets as every other node does: a self contact at the tip's
    // arc length appears, and the assembled tangent with it is the
    // derivative of the residual.
    fem::RodModel m(contact_scene("Injection/Channel positions=0.5"));
    int checked = 0;
    while (m.injected_length() < 60.0 && checked < 3)
      {
        m.step();
        const auto w = m.wire_state();
        const double tip = w.arc_length.back();
        const bool at_tip = std::any_of(w.self_contacts.begin(), w.self_contacts.end(), [&](const auto &c) {
          return std::abs(c.s_a - tip) < 1e-9 || std::abs(c.s_b - tip) < 1e-9;
        });
        if (at_tip && m.n_steps() % 5 == 0)
          {
            const double err = fem::RodModelProbe::step_checking_tangent(m);
            EXPECT_GE(err, 0.0) << "the check did not run";
            EXPECT_LT(err, 1e-6) << "at L = " << m.injected_length();
            ++checked;
          }
      }
    EXPECT_EQ(checked, 3) << "too few steps with the tip in self contact";
  }

  TEST(RodModel, ModifiedNewtonSavesAndLoadsBitForBit)
  {
    // Every step starts from a tangent at its predictor, so no factors
    // outlive a step and the checkpoint holds all that the run depends on.
    const auto s = contact_scene("FEM/Newton=modified");
    fem::RodModel straight(s), first(s), resumed(s);
    checks::run_straight_and_resumed(straight, first, resumed, 38.0, 45.0);
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
  }

  /// Friction springs are state: a run resumed from a checkpoint at the
  /// first step from L = 36 on where `holds` says there are springs to lose
  /// continues bit for bit to 45, and one that forgets them after loading
  /// (`forget`) does not, from that checkpoint or one 2 or 4 later (a
  /// spring may hold a contact that opens at once, so one checkpoint alone
  /// may not show it).
  void expect_springs_in_checkpoint(const scene::Scene &s, const std::function<bool(fem::RodModel &)> &holds,
                                    const std::function<void(fem::RodModel &)> &forget)
  {
    fem::RodModel straight(s), first(s), resumed(s);
    while (first.injected_length() < 36.0 || !holds(first))
      {
        first.step();
        ASSERT_LT(first.injected_length(), 41.0) << "no spring to lose at L = 36 to 41";
      }
    const double checkpoint = first.injected_length();
    checks::run_straight_and_resumed(straight, first, resumed, checkpoint, 45.0);
    EXPECT_EQ(straight.n_steps(), resumed.n_steps());
    EXPECT_EQ(straight.time(), resumed.time());
    EXPECT_EQ(largest_distance(straight, resumed), 0.0);
    double lost = 0.0;
    for (const double at : {checkpoint, checkpoint + 2.0, checkpoint + 4.0})
      {
        while (first.injected_length() < at)
          first.step();
        if (!holds(first))
          continue;
        std::stringstream buffer;
        first.save(buffer);
        fem::RodModel forgetful(s);
        forgetful.load(buffer);
        forget(forgetful);
        while (forgetful.injected_length() < 45.0)
          forgetful.step();
        lost = largest_distance(straight, forgetful);
        if (lost > 1e-9)
          break;
      }
    EXPECT_GT(lost, 1e-9) << "forgetting the springs changed nothing";
  }

  TEST(RodModel, WallSpringsAreInTheCheckpoint)
  {
    // Under the spring law each wall contact's spring is state: a run
    // resumed from a checkpoint continues bit for bit, and the same
    // checkpoint with its springs zeroed after loading does not. The wire
    // is elastic with mu_st = 5, so that some contacts stick.
    expect_springs_in_checkpoint(
        fem_scene({"Wire/Plasticity/Enabled=false", "Contact/Friction/Static coefficient=5",
                   "FEM/Friction law=spring"}),
        [](fem::RodModel &first) {
          const auto &springs = fem::RodModelProbe::wall_springs(first);
          return std::any_of(springs.begin(), springs.end(),
                             [](const auto &h) { return h.elongation != 0.0 && !h.sliding; });
        },
        [](fem::RodModel &forgetful) {
          for (auto &h : fem::RodModelProbe::wall_springs(forgetful))
            h = contact::FrictionHistory{};
        });
  }

  TEST(RodModel, SelfSpringsAreInTheCheckpointAndTheirTangentIsTheDerivative)
  {
    // FEM/Self friction law = spring: some self contacts stick; the
    // assembled tangent with their springs is the derivative of the
    // residual; the springs are state, so a resumed run continues bit for
    // bit and one that forgets them does not; the ledger closes with the
    // springs' energy stored, not dissipated (at the shipped speed: at 1
    // the step's error alone misses 1%, under either law).
    const std::vector<std::string> keys{"Wire/Plasticity/Enabled=false",
                                        "Contact/Friction/Static coefficient=5",
                                        "FEM/Self friction law=spring"};
    const auto s = fem_scene(keys);
    auto slow_keys = keys;
    slow_keys.push_back("Injection/Speed=0.3");
    fem::RodModel probed(fem_scene(slow_keys));
    int checked = 0;
    while (probed.injected_length() < 45.0)
      {
        const bool sticking =
            std::any_of(fem::RodModelProbe::self_springs(probed).all().begin(),
                        fem::RodModelProbe::self_springs(probed).all().end(),
                        [](const fem::PairSpring &p) { return p.sliding == 0 && p.elongation != 0.0; });
        if (sticking && probed.n_steps() % 20 == 0)
          {
            const double err = fem::RodModelProbe::step_checking_tangent(probed);
            EXPECT_GE(err, 0.0) << "the check did not run";
            EXPECT_LT(err, 1e-6) << "at L = " << probed.injected_length();
            ++checked;
          }
        else
          probed.step();
      }
    EXPECT_GE(checked, 3) << "too few steps with a sticking self contact";
    const auto &e = probed.energies();
    EXPECT_GT(e.friction, 0.0);
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;

    expect_springs_in_checkpoint(
        s, [](fem::RodModel &first) { return !fem::RodModelProbe::self_springs(first).all().empty(); },
        [](fem::RodModel &forgetful) { fem::RodModelProbe::self_springs(forgetful).commit({}); });
  }

  TEST(RodModel, SpringLawBooksTheWallSpringsEnergy)
  {
    // What the wall springs hold is stored energy (zero when no spring is
    // loaded), not friction work: with it the ledger balances as tightly
    // as under the regularised law.
    // The springs between wires (Self friction law = auto) would store
    // energy too.
    fem::RodModel m(fem_scene({"Wire/Plasticity/Yield curvature=0.05", "FEM/Friction law=spring",
                               "FEM/Self friction law=regularised"}));
    double most = 0.0;
    while (m.injected_length() < 45.0)
      {
        m.step();
        const auto &springs = fem::RodModelProbe::wall_springs(m);
        const bool loaded =
            std::any_of(springs.begin(), springs.end(), [](const auto &h) { return h.elongation != 0.0; });
        EXPECT_EQ(m.energies().friction_stored > 0.0, loaded) << "at t = " << m.time();
        most = std::max(most, m.energies().friction_stored);
      }
    const auto &e = m.energies();
    EXPECT_GT(most, 0.0);
    EXPECT_GT(e.friction, 0.0);
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;
    EXPECT_LT(m.report().max_penetration, 0.1);
  }

  TEST(RodModel, ExplicitStepsLoadTheWallSprings)
  {
    // The explicit integrator takes its forces at the start of the step:
    // its wall springs stretch by the motion over the step before, so the
    // walls hold (some springs stick), friction does work and the ledger
    // closes. Without self contact: the next test has it.
    fem::RodModel m(fem_scene({"FEM/Integrator=explicit", "Wire/Plasticity/Enabled=false",
                               "Contact/Friction/Static coefficient=5", "FEM/Friction law=spring",
                               "Contact/Self contact=false"}));
    int sticking = 0;
    while (m.injected_length() < 30.0)
      {
        m.step();
        const auto &springs = fem::RodModelProbe::wall_springs(m);
        sticking += std::any_of(springs.begin(), springs.end(),
                                [](const auto &h) { return h.elongation != 0.0 && !h.sliding; });
      }
    const auto &e = m.energies();
    EXPECT_GT(sticking, 100);
    EXPECT_GT(e.friction, 0.0);
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;
  }

  TEST(RodModel, ExplicitStepsKeepStrongSelfFrictionInTheLedger)
  {
    // Regularised self friction at mu_st = 5 damps a contact's slip at a
    // rate of up to 2 mu_st F_n / (v_th m); explicit in the rate, a step
    // past 2 / rate overshoots and swings. The explicit step stays below
    // 1 / rate of the stiffest contact. At the cap alone the ledger here
    // misses 18% (and 30% on prm/classic.prm at f = 8); with the bound it
    // closes, and the bound, not the cap, sets most steps.
    fem::RodModel m(fem_scene(
        {"FEM/Integrator=explicit", "Contact/Friction/Static coefficient=5", "FEM/Friction law=spring"}));
    const double cap = fem::RodModelProbe::step_cap(m);
    std::size_t most_pairs = 0;
    int bound = 0;
    while (m.injected_length() < 30.0)
      {
        m.step();
        if (m.n_steps() % 100 == 0)
          most_pairs = std::max(most_pairs, m.wire_state().self_contacts.size());
        bound += m.time_step() < 0.5 * cap;
      }
    const auto &e = m.energies();
    EXPECT_GE(most_pairs, 2u);
    EXPECT_GT(bound, 100);
    EXPECT_GT(e.friction, 0.0);
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;
    EXPECT_LT(m.report().max_penetration, 0.1);
  }

  TEST(RodModel, AStepThatConvergesOnItsLastAllowedIterationIsTaken)
  {
    // The first step takes k Newton iterations; with Maximum iterations =
    // k it must be taken as it is, not cut (the residual after the last
    // solve is checked too), and with k - 1 it is cut.
    fem::RodModel free_run(contact_scene("FEM/Maximum iterations=50"));
    free_run.step();
    ASSERT_EQ(free_run.n_step_cuts(), 0u);
    const unsigned long k = fem::RodModelProbe::newton_iterations(free_run);
    ASSERT_GE(k, 2u);
    fem::RodModel exact(contact_scene(fmt::format("FEM/Maximum iterations={}", k)));
    exact.step();
    EXPECT_EQ(exact.n_step_cuts(), 0u);
    EXPECT_EQ(fem::RodModelProbe::newton_iterations(exact), k);
    EXPECT_EQ(exact.time(), free_run.time());
    fem::RodModel short_of_it(contact_scene(fmt::format("FEM/Maximum iterations={}", k - 1)));
    short_of_it.step();
    EXPECT_GT(short_of_it.n_step_cuts(), 0u);
  }

  TEST(RodModel, StatisticsCountTheSolversWork)
  {
    // What summary.json records as solver_statistics on the injection
    // scenes, against the counters it is read from.
    fem::RodModel m(
        fem_scene({"Wire/Plasticity/Yield curvature=0.05", "Contact/Friction/Static coefficient=0.5",
                   "FEM/Overlap growth=0.004", "FEM/Step error=1e-4"}));
    while (m.injected_length() < 20.0)
      m.step();
    std::map<std::string, double> stats;
    for (const auto &[key, value] : m.statistics())
      stats[key] = value;
    const auto &ls = fem::RodModelProbe::linear_statistics(m);
    EXPECT_EQ(stats.size(), 5u);
    EXPECT_EQ(stats["newton_iterations"], fem::RodModelProbe::newton_iterations(m));
    EXPECT_GT(stats["newton_iterations"], 0.0);
    EXPECT_EQ(stats["step_cuts"], m.n_step_cuts());
    EXPECT_EQ(stats["overlap_cuts"], fem::RodModelProbe::overlap_cuts(m));
    EXPECT_GT(stats["overlap_cuts"], 0.0);
    EXPECT_EQ(stats["error_cuts"], fem::RodModelProbe::error_cuts(m));
    EXPECT_GT(stats["error_cuts"], 0.0);
    EXPECT_EQ(stats["factorisations"], ls.factorisations + ls.refactorisations);
    EXPECT_GT(stats["factorisations"], 0.0);
  }

  TEST(RodModel, AStepThatFailsWithInexactSolvesIsRetriedWithAnLUBeforeItIsCut)
  {
    // GMRES on kept factors stopped at 0.9 of the residual makes Newton
    // converge too slowly for 3 iterations: such steps fail, are retried
    // with an LU per iteration, and are cut only where that fails as well,
    // at the same steps as in a run with an LU throughout. (GMRES on the
    // band's LU is retried the same way; on this scene, with few contacts,
    // its first iteration already solves nearly exactly.)
    const auto run = [](const std::string &solver) {
      fem::RodModel m(
          fem_scene({"FEM/Linear solver=" + solver, "FEM/Linear tolerance=0.9", "FEM/Maximum iterations=3",
                     "FEM/Step error=0",             // fixed steps, so that both runs cut the same ones
                     "FEM/Newton tolerance=1e-8"})); // that 3 slow iterations do not reach
      for (int i = 0; i < 200; ++i)
        m.step();
      return std::make_tuple(fem::RodModelProbe::retried_steps(m), m.n_step_cuts(), m.time());
    };
    const auto [retried, cuts, time] = run("kept factors");
    const auto [lu_retried, lu_cuts, lu_time] = run("refactorise");
    EXPECT_EQ(lu_retried, 0u);
    EXPECT_GT(retried, cuts + 50) << "steps rescued by the retry";
    EXPECT_EQ(cuts, lu_cuts);
    EXPECT_EQ(time, lu_time);
  }

  TEST(RodModel, EnergyBalanceAndOverlapOverARun)
  {
    fem::RodModel m(fem_scene({"Wire/Plasticity/Yield curvature=0.05"}));
    while (m.injected_length() < 45.0)
      m.step();
    const auto &e = m.energies();
    EXPECT_GT(m.report().n_self_contacts + m.report().n_wall_contacts, 0);
    EXPECT_GT(e.plastic, 0.0);
    EXPECT_GT(e.friction, 0.0);
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;
    EXPECT_LT(m.report().max_penetration, 0.1);
  }
  TEST(RodModel, TangentialChannelsStartOnAnSAndWindOntoTheWall)
  {
    // As the discrete model's test (discrete_test.cc), in the FEM: an
    // elastic, frictionless wire from the S between tangential inlets.
    const auto s = scene::read_scene("", {"Model=fem", "Cavity/Radius=10", "Injection/Speed=1",
                                          "Injection/Channels=tangential", "Wire/Plasticity/Enabled=false",
                                          "Contact/Friction/Static coefficient=0",
                                          "Injection/Maximum packing density=0.5", "Output/Progress=off"});
    fem::RodModel m(s);
    const double r_inlet = 9.5, rho = 0.5 * r_inlet, l0 = M_PI * r_inlet;
    EXPECT_DOUBLE_EQ(m.injected_length(), l0);
    {
      // The free nodes on the two half circles (the first half circle
      // below the x axis), and the curvature +-1/rho on the elements that
      // lie wholly on one of them.
      const auto w = m.wire_state();
      const auto n = w.points.size();
      ASSERT_GT(n, 20u);
      EXPECT_EQ(w.points.front().x, -r_inlet);
      EXPECT_EQ(w.points.back().x, r_inlet);
      int checked = 0;
      for (std::size_t k = 1; k + 1 < n; ++k)
        {
          const Vec2 p = w.points[k];
          const double sk = w.arc_length[k];
          const bool first_half = sk < 0.5 * l0;
          EXPECT_EQ(p.y < 0.0, first_half) << "node " << k;
          EXPECT_NEAR(norm(p - Vec2{first_half ? -rho : rho, 0.0}), rho, 1e-12) << "node " << k;
          if (sk > 2.0 && sk < l0 - 2.0 && std::abs(sk - 0.5 * l0) > 2.0)
            {
              EXPECT_NEAR(w.curvature[k], first_half ? 1.0 / rho : -1.0 / rho, 1e-9) << "node " << k;
              ++checked;
            }
        }
      EXPECT_GT(checked, 15);
    }
    const injection::Channels ch(10.0, 1.0, 10.0);
    while (m.injected_length() < 0.4 * M_PI * 100.0)
      m.step();
    EXPECT_DOUBLE_EQ(m.injected_length(), l0 + 2.0 * ch.injected_per_channel(m.time()));
    const auto &e = m.energies();
    EXPECT_LT(std::abs(e.balance_error()), 0.01) << "in " << e.initial + e.injection_work;
    EXPECT_LT(m.report().max_penetration, 0.1);
    EXPECT_GT(m.report().n_wall_contacts, 0);
    // The outermost turn lies on the wall: nodes near r' all round.
    const auto w = m.wire_state();
    std::vector<double> outermost(8, 0.0);
    for (const Vec2 p : w.points)
      {
        const double angle = std::atan2(p.y, p.x) + M_PI;
        auto &o = outermost[std::min(7, static_cast<int>(angle / (0.25 * M_PI)))];
        o = std::max(o, norm(p));
      }
    for (const double o : outermost)
      EXPECT_GT(o, r_inlet - 0.1);
  }

  TEST(FemCapstan, AssembledTangentIsTheDerivativeOfTheAssembledResidual)
  {
    // Full end force from the first step (no ramp), so the follower force,
    // the end moment, the friction and the trailing end all enter the
    // compared tangent (at the predictor of the second step, where the
    // friction is engaged); the roller and the held trailing end.
    auto s =
        scene::read_scene("", {"Set-up=capstan", "Model=fem", "Cavity/Radius=25",
                               "Wire/Plasticity/Enabled=false", "Capstan/End force=10", "Capstan/Ramp time=0",
                               "Capstan/Slide=0.5", "Contact/Friction/Wall static coefficient=0.3",
                               "Contact/Friction/Wall dynamic coefficient=0.24"});
    for (const bool roller : {true, false})
      {
        s.capstan.trailing_roller = roller;
        fem::RodModel rod(s);
        rod.step();
        // Central differences reach 2.5e-8 here; a missing follower-force
        // term gives 2.4e-3.
        EXPECT_LT(fem::RodModelProbe::step_checking_tangent(rod), 1e-6)
            << roller; // 2.6e-3 without the follower's
      }
  }

  /// The capstan run of a scene through the production driver.
  simulation::CapstanResult run_capstan_in(scene::Scene s, const std::string &name)
  {
    s.output.directory = testing::TempDir() + name;
    return simulation::run_capstan(s, {false, true}); // replaces an earlier test run
  }

  double statistic(const core::Model &m, const std::string &key)
  {
    for (const auto &[k, v] : m.statistics())
      if (k == key)
        return v;
    return NAN;
  }

  TEST(FemCapstan, SlidingFollowsTheCapstanLaw)
  {
    // A nearly inextensible rod (EA = 1e5) on the wall over pi/2, slid
    // against T0 = 1: its push force is T0 exp(mu_V Theta), with mu_V the
    // regularised law's coefficient at the push speed.
    const auto s = scene::read_scene(
        "", {"Set-up=capstan", "Model=fem", "Cavity/Radius=25", "Wire/Plasticity/Enabled=false",
             "Wire/Axial stiffness=1e5", "FEM/Element length=0.25",
             "Contact/Friction/Wall static coefficient=0.3", "Contact/Friction/Wall dynamic coefficient=0.24",
             "FEM/Friction law=regularised"});
    const auto r = run_capstan_in(s, "fem_capstan_sliding");
    ASSERT_TRUE(r.finished);
    EXPECT_NEAR(r.wrap_angle, 0.5 * M_PI, 1e-12);
    const double x = 0.05 / 0.01, mu = (0.24 + 0.06 * std::exp(-x)) * std::tanh(x);
    EXPECT_NEAR(statistic(fem::RodModel(s), "sliding_coefficient"), mu, 1e-15);
    EXPECT_NEAR(r.push_force / std::exp(mu * r.wrap_angle), 1.0, 2e-6); // 4.5e-7 measured (O(h^2))
  }

  TEST(FemCapstan, SpringLawSlipsAtTheStaticCapstanLaw)
  {
    // Force control with the spring law: a nearly inextensible rod on the
    // wall over pi/2 holds until the push reaches T0 exp(mu Theta) (mu_d =
    // mu_st: a sharp threshold), and the tangent includes the free pushed
    // end's follower force and the sticking springs.
    const auto s = scene::read_scene(
        "",
        {"Set-up=capstan", "Model=fem", "Cavity/Radius=25", "Wire/Plasticity/Enabled=false",
         "Wire/Axial stiffness=1e5", "FEM/Element length=0.5", "FEM/Friction law=spring",
         "Capstan/Control=force", "Capstan/Ramp time=10", "Capstan/Force rate=1e-3",
         "Contact/Friction/Wall static coefficient=0.3", "Contact/Friction/Wall dynamic coefficient=0.3"});
    {
      // The tangent at the first predictor with the full loads (no ramp):
      // the wire sticks there, off the return map's kink (every later
      // predictor of force control starts on it: no slip yet, the spring at
      // the limit it slid at).
      auto full = s;
      full.capstan.ramp_time = 0.0;
      fem::RodModel rod(full);
      EXPECT_LT(fem::RodModelProbe::step_checking_tangent(rod), 1e-6);
    }
    const auto r = run_capstan_in(s, "fem_capstan_spring");
    ASSERT_TRUE(r.finished);
    const double law = std::exp(0.3 * r.wrap_angle);
    EXPECT_NEAR(r.onset_force / law, 1.0, 2e-3) << r.onset_force << " " << law;
  }

  TEST(FemCantilever, PastTheEulerLoadNewtonKeepsToTheStableBranchOfTheImperfection)
  {
    // Half of a pinned-pinned rod at 1.5 and 3 times the Euler load, with a
    // transverse imperfection of 1e-3 P up or down: load-controlled Newton
    // must end on a stable state (positive lowest eigenvalue of the tangent)
    // buckled to the side of the imperfection, well away from straight.
    const double L = 20.0, EI = 60.0, P_cr = M_PI * M_PI * EI / (4.0 * L * L);
    for (const double ratio : {1.5, 3.0})
      for (const double side : {1.0, -1.0})
        {
          const double P = ratio * P_cr;
          const auto s = scene::read_scene("", {"Set-up=cantilever", "Model=fem", "FEM/Degree=2",
                                                "FEM/Element length=2.5", "Wire/Plasticity/Enabled=false",
                                                "Cantilever/Tolerance=1e-10",
                                                "Cantilever/End force x=" + std::to_string(-P),
                                                "Cantilever/End force y=" + std::to_string(side * 1e-3 * P)});
          fem::RodModel rod(s);
          const auto eq = rod.equilibrate(1.0);
          ASSERT_TRUE(eq.converged) << ratio;
          double lowest = NAN;
          for (const auto &[key, value] : rod.statistics())
            if (key == "lowest_eigenvalue")
              lowest = value;
          EXPECT_GT(lowest, 0.0) << ratio << " " << side;
          EXPECT_GT(side * eq.tip_y, 0.25 * L) << ratio << " " << side;   // mid-span deflection
          EXPECT_GT(side * eq.tip_rotation, 1.0) << ratio << " " << side; // end slope (rad)
        }
  }
} // namespace
