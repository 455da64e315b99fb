// Pieces shared by the contact kernels of the rod FEM (not installed):
// contact_element.cc (the kernels, and the automatic-differentiation
// oracles) and wall_contact_spring.cc (the wall under the spring law by
// hand).
#pragma once

#include <wirefem/core/vec2.h>
#include <wirefem/fem/contact_element.h>

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
