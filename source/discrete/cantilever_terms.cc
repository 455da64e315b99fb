#include <wirefem/discrete/terms.h>

#include <cmath>

namespace wirefem::discrete
{
  using core::Vec2;

  ClampTerm::ClampTerm(const material::MomentCurvatureLaw &clamp_law, const Vec2 direction)
    : law(clamp_law)
    , direction((1.0 / norm(direction)) * direction)
  {
  }

  double ClampTerm::angle(const Chain &c) const
  {
    const Vec2 b = c.x[c.first + 1] - c.x[c.first];
    return std::atan2(cross(direction, b), dot(direction, b));
  }

  void ClampTerm::add_forces(Chain &c, double, StepEnergy &e)
  {
    const Vec2 b = c.x[c.first + 1] - c.x[c.first];
    const double zeta = angle(c);
    const double moment = spring_moment(law, zeta, &state, &trial_state, e);
    // d zeta / d x_{first+1} = perp(b)/|b|^2; the clamp node takes the reaction.
    const Vec2 g = (1.0 / norm_square(b)) * perp(b);
    c.f[c.first + 1] -= moment * g;
    c.f[c.first] += moment * g;
  }

  EndLoadTerm::EndLoadTerm(const Vec2 force, const double moment)
    : force(force)
    , moment(moment)
  {
  }

  double EndLoadTerm::end_angle(const Chain &c) const
  {
    const Vec2 b = c.x[c.last - 1] - c.x[c.last - 2];
    const double raw = std::atan2(b.y, b.x);
    return committed_angle + std::remainder(raw - committed_angle, 2.0 * M_PI);
  }

  double EndLoadTerm::potential(const Chain &c) const
  {
    return -factor * (dot(force, c.x[c.last - 1]) + moment * end_angle(c));
  }

  void EndLoadTerm::add_forces(Chain &c, double, StepEnergy &e)
  {
    e.load_potential += potential(c);
    const int n = c.last - 1;
    const Vec2 b = c.x[n] - c.x[n - 1];
    trial_angle = end_angle(c);
    const Vec2 g = (1.0 / norm_square(b)) * perp(b); // d phi / d x_N
    c.f[n] += factor * (force + moment * g);
    c.f[n - 1] -= factor * moment * g;
  }

  EndThrustTerm::EndThrustTerm(const End end, const double thrust, const double moment)
    : end(end)
    , thrust(thrust)
    , moment(moment)
  {
  }

  void EndThrustTerm::add_forces(Chain &c, double, StepEnergy &e)
  {
    const int k = end == End::first ? c.first : c.last - 1;     // the end node
    const int j = end == End::first ? c.first + 1 : c.last - 2; // its neighbour
    const Vec2 b = c.x[k] - c.x[j];                             // outward along the end segment
    const double length = norm(b);
    e.load_potential -= moment * std::atan2(b.y, b.x);
    const Vec2 g = (1.0 / (length * length)) * perp(b); // d phi / d x_k
    c.f[k] += (-thrust / length) * b + moment * g;
    c.f[j] -= moment * g;
  }
} // namespace wirefem::discrete
