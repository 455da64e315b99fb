// A discrete force term against finite differences of its energy: the
// check every term's test makes.
#pragma once

#include <wirefem/discrete/terms.h>

#include <gtest/gtest.h>

#include <algorithm>

namespace wirefem::test
{
  using core::Vec2;
  using discrete::Chain;
  using discrete::StepEnergy;

  inline double potential(const StepEnergy &e)
  {
    return e.stretching + e.bending + e.contact + e.friction_stored + e.load_potential;
  }

  // Checks f = -dE/dx for every coordinate of every active node.
  inline void expect_forces_match_energy(discrete::Term &term, Chain chain, const double tolerance)
  {
    auto energy_at = [&](Chain &c) {
      StepEnergy e;
      std::fill(c.f.begin(), c.f.end(), Vec2{});
      term.add_forces(c, 1e-3, e);
      return potential(e);
    };
    energy_at(chain);
    const auto forces = chain.f;
    double scale = 0.0;
    for (int k = chain.first; k < chain.last; ++k)
      scale = std::max(scale, norm(forces[k]));
    ASSERT_GT(scale, 0.0) << "the configuration does not load the term";
    const double h = 1e-6;
    for (int k = chain.first; k < chain.last; ++k)
      for (int dim = 0; dim < 2; ++dim)
        {
          Chain plus = chain, minus = chain;
          (dim ? plus.x[k].y : plus.x[k].x) += h;
          (dim ? minus.x[k].y : minus.x[k].x) -= h;
          const double fd = -(energy_at(plus) - energy_at(minus)) / (2 * h);
          const double f = dim ? forces[k].y : forces[k].x;
          EXPECT_NEAR(f, fd, tolerance * scale) << term.name() << ": node " << k << " dim " << dim;
        }
  }

} // namespace wirefem::test
