// Pieces of the injection that both models share: the seeded initial shape
// of the wire across the cavity and the inlet force as channel work per
// injected length.
#pragma once

#include <cmath>
#include <deque>
#include <random>
#include <utility>

namespace wirefem::injection
{
  /// Transverse offset of the initial wire across the cavity (span 2 r):
  /// the first buckling mode of a clamped-clamped rod, (1 - cos(2 pi xi / 2r)) / 2,
  /// up or down as the seed says, plus random clamped modes 2..6 at a tenth
  /// of its amplitude that break the mirror symmetry slightly. Seeding mostly
  /// the first mode lets the wire buckle into one arch, as in the paper,
  /// instead of the faster-growing short modes of a rod loaded quickly. The
  /// raw 32-bit draws of mt19937 are the same on every platform, so a seed
  /// gives the same wire everywhere.
  class InitialShape
  {
  public:
    /// mirror_asymmetry scales the modes that are antisymmetric about the
    /// axis between the inlets (odd m): 1 as drawn, 0 a mirror-symmetric start.
    InitialShape(unsigned int seed, double amplitude, double span, double mirror_asymmetry = 1.0)
      : amplitude(amplitude)
      , span(span)
    {
      std::mt19937 gen(seed);
      auto uniform = [&gen]() { return 2.0 * (gen() / 4294967295.0) - 1.0; };
      const double sign = (gen() & 1u) ? 1.0 : -1.0;
      amp[0] = sign;
      for (int m = 1; m < 6; ++m)
        amp[m] = 0.1 * uniform() * (m % 2 ? mirror_asymmetry : 1.0);
    }

    /// Offset at distance xi in [0, span] from the left inlet.
    double offset(const double xi) const
    {
      double y = 0.0;
      for (int m = 0; m < 6; ++m)
        y += amp[m] * 0.5 * (1.0 - std::cos(2.0 * M_PI * (m + 1) * xi / span)) *
             (m % 2 ? std::cos(M_PI * xi / span) : 1.0); // odd m: antisymmetric
      return amplitude * y;
    }

    /// d offset / d xi (central difference; the shape is smooth).
    double slope(const double xi) const
    {
      const double e = 1e-6 * span;
      return (offset(xi + e) - offset(xi - e)) / (2.0 * e);
    }

  private:
    double amplitude, span;
    double amp[6] = {0, 0, 0, 0, 0, 0};
  };

  /// Work of one channel over the last `length` of injection: the inlet
  /// force as work per injected length. A node passes the inlet once per
  /// node spacing, so a window of that length removes the step of the
  /// discrete moving boundary exactly.
  struct ForceWindow
  {
    double length = 1.0;
    std::deque<std::pair<double, double>> steps; // (injected, work)
    double injected = 0.0, work = 0.0;

    void add(const double du, const double dw)
    {
      steps.emplace_back(du, dw);
      injected += du;
      work += dw;
      while (steps.size() > 1 && injected - steps.front().first >= length)
        {
          injected -= steps.front().first;
          work -= steps.front().second;
          steps.pop_front();
        }
    }
    double mean() const { return injected > 0.0 ? work / injected : 0.0; }
  };
} // namespace wirefem::injection
