// Pieces shared by the contact kernels of the rod FEM (not installed):
// contact_element.cc (the kernels, and the automatic-differentiation
// oracles), wall_contact_spring.cc (the wall under the spring law by
// hand) and self_friction_element.cc (the self contact's spring law).
#pragma once

#include <wirefem/core/vec2.h>
#include <wirefem/fem/contact_element.h>

#include <array>
#include <cmath>

namespace wirefem::fem::detail
{
  /// Clears `out` for a contact of n points, keeping its want_tangent;
  /// returns its number of dofs.
  inline int start_contribution(ContactContribution &out, const int n)
  {
    const bool want_tangent = out.want_tangent;
    out = ContactContribution{};
    out.n_points = n;
    out.want_tangent = want_tangent;
    return 2 * n;
  }

  /// Where the closest point of x[1]-x[2] to x[0] lies (n == 3; a point
  /// against a point, n == 2, has t = 0): e = x2 - x1, t clamped to [0, 1],
  /// and dt/dx_j (zero when clamped).
  struct ClosestParameter
  {
    core::Vec2 e{0.0, 0.0};
    double t = 0.0;
    std::array<core::Vec2, 3> dt{};
  };

  inline ClosestParameter closest_parameter(const int n, const core::Vec2 *x)
  {
    ClosestParameter p;
    if (n != 3)
      return p;
    p.e = x[2] - x[1];
    const core::Vec2 w = x[0] - x[1];
    const double ee = dot(p.e, p.e);
    p.t = dot(w, p.e) / ee;
    if (p.t <= 0.0)
      p.t = 0.0;
    else if (p.t >= 1.0)
      p.t = 1.0;
    else
      {
        p.dt[0] = (1.0 / ee) * p.e;
        p.dt[2] = (1.0 / ee) * (w - 2.0 * p.t * p.e);
        p.dt[1] = -1.0 * (p.dt[0] + p.dt[2]);
      }
    return p;
  }

  /// Where x meets the circle of radius r with the radial channels'
  /// mouths (mouths false: a closed circle): within a mouth's opening the
  /// contact is with its corner, elsewhere with the circle. False when x
  /// (a wire of diameter d) touches neither.
  inline bool circle_wall_touches(const double radius, const double diameter, const bool mouths,
                                  const core::Vec2 &x, bool &in_opening, core::Vec2 &corner)
  {
    const double half_d = 0.5 * diameter;
    const double dist = norm(x);
    in_opening = mouths && std::abs(x.y) * radius < half_d * dist;
    if (!in_opening && dist + half_d - radius <= 0.0)
      return false; // most points: inside, away from the mouths
    corner = {x.x > 0.0 ? std::sqrt(radius * radius - half_d * half_d)
                        : -std::sqrt(radius * radius - half_d * half_d),
              x.y > 0.0 ? half_d : -half_d};
    return !(in_opening && half_d - norm(corner - x) <= 0.0);
  }
} // namespace wirefem::fem::detail
