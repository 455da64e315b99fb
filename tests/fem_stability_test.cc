// Whether the states the quasi-static FEM steps through are held by
// friction: stable when every contact holds (its stick stiffness in the
// tangent), often unstable without friction. Newton finds equilibria,
// stable or not, so nothing else would show a path that runs where even
// sticking contacts could not hold the wire.
#include "rod_probe.h"
#include <wirefem/analysis/observables.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/scene/scene_reader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iostream>
#include <vector>

namespace wirefem
{
  namespace
  {
    double lowest_real_part(const std::vector<std::complex<double>> &lambda)
    {
      double lowest = INFINITY;
      for (const auto &l : lambda)
        lowest = std::isfinite(l.real()) && std::isfinite(l.imag()) ? std::min(lowest, l.real()) : NAN;
      return lowest;
    }
  } // namespace

  TEST(RodModel, QuasiStaticInjectionStatesAreHeldByFriction)
  {
    // The elastic wire of prm/classic.prm (mu_st 5, speed 0.3), the scene
    // where the quasi-static FEM jams below the slow dynamic models, at
    // f = 8 to phi 0.45. Every 20th step: the eigenvalues of the tangent at
    // rest (every contact holding), without the dashpots; a negative real
    // part is a disturbance that grows even so. Without friction's part
    // many of the same states are unstable: friction holds them, and the
    // check can report an instability.
    const double radius = 8.0;
    fem::RodModel m(scene::read_scene(
        "", {"Model=fem", "Cavity/Radius=8", "Output/Progress=off", "Wire/Plasticity/Enabled=false",
             "Contact/Friction/Static coefficient=5", "Injection/Speed=0.3", "FEM/Integrator=quasi-static"}));
    int samples = 0, unstable = 0, unstable_without_friction = 0, steps = 0;
    double lowest = INFINITY;
    bool finite = true;
    while (analysis::packing_density(m.injected_length(), radius) < 0.45)
      {
        m.step();
        if (++steps % 20 != 0 || fem::RodModelProbe::in_dynamic_phase(m))
          continue;
        ++samples;
        const double with = lowest_real_part(fem::RodModelProbe::tangent_eigenvalues_at_rest(m, true));
        const double without = lowest_real_part(fem::RodModelProbe::tangent_eigenvalues_at_rest(m, false));
        finite = finite && std::isfinite(with) && std::isfinite(without);
        lowest = std::min(lowest, with);
        unstable += with < 0.0 ? 1 : 0;
        unstable_without_friction += without < 0.0 ? 1 : 0;
      }
    std::cout << samples << " states, " << unstable << " unstable (lowest real part " << lowest << "), "
              << unstable_without_friction << " unstable without friction\n";
    EXPECT_TRUE(finite);
    EXPECT_GE(samples, 50);
    EXPECT_EQ(unstable, 0) << "lowest real part " << lowest;
    EXPECT_GT(unstable_without_friction, samples / 8);
  }
} // namespace wirefem
