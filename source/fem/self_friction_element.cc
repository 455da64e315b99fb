// The discrete model's friction law on a self contact of the rod FEM
// (FEM/Self friction law = spring), with its tangent by automatic
// differentiation.
#include <wirefem/fem/contact_element.h>

#include <Sacado.hpp>

#include <cmath>

namespace wirefem::fem
{
  namespace
  {
    using Fad = Sacado::Fad::SLFad<double, 6>; // 6 coordinates: no heap
    using core::Vec2;

    struct P
    {
      Fad x, y;
    };
  } // namespace

  bool point_segment_spring_friction(const ContactSettings &s, const double weight,
                                     const double stiffness_ratio, const std::array<Vec2, 3> &x,
                                     const std::array<Vec2, 3> &x_old, const double dt,
                                     const contact::FrictionHistory &old, ContactContribution &out,
                                     SpringFriction &friction, const double friction_scale)
  {
    P p[3];
    for (int m = 0; m < 3; ++m)
      p[m] = {Fad(6, 2 * m, x[m].x), Fad(6, 2 * m + 1, x[m].y)};
    const Fad ex = p[2].x - p[1].x, ey = p[2].y - p[1].y;
    Fad t = ((p[0].x - p[1].x) * ex + (p[0].y - p[1].y) * ey) / (ex * ex + ey * ey);
    if (t.val() <= 0.0)
      t = 0.0;
    else if (t.val() >= 1.0)
      t = 1.0;
    const Fad dx = p[0].x - (p[1].x + t * ex), dy = p[0].y - (p[1].y + t * ey);
    const Fad dist = sqrt(dx * dx + dy * dy);
    if (dist.val() >= s.diameter || dist.val() < 1e-12 * s.diameter)
      return false;
    out = ContactContribution{};
    out.n_points = 3;
    const double k = s.stiffness * weight, kt = stiffness_ratio * k;
    const Fad fn = k * (s.diameter - dist);
    const Fad tx = -dy / dist, ty = dx / dist;
    const auto moved = [&](const int m, const bool y) -> Fad {
      return y ? p[m].y - x_old[m].y : p[m].x - x_old[m].x;
    };
    const Fad slip = (moved(0, false) - (1.0 - t) * moved(1, false) - t * moved(2, false)) * tx +
                     (moved(0, true) - (1.0 - t) * moved(1, true) - t * moved(2, true)) * ty;
    // As wall_contact_spring: the cap from the state the step starts from.
    const double slide = spring_step(s, kt, fn.val(), slip.val(), dt, old, friction);
    const Fad ft = slide == 0.0 ? Fad(-kt * (old.elongation + slip)) : Fad(slide * fn);
    // Force ft tau on the point, -(1 - t) ft tau and -t ft tau on the ends.
    const Fad share[3] = {Fad(1.0), -(1.0 - t), -t};
    for (int m = 0; m < 3; ++m)
      {
        const Fad rx = -share[m] * ft * tx, ry = -share[m] * ft * ty;
        out.residual[2 * m] = out.friction_residual[2 * m] = rx.val();
        out.residual[2 * m + 1] = out.friction_residual[2 * m + 1] = ry.val();
        for (int j = 0; j < 6; ++j)
          {
            out.tangent[(2 * m) * 6 + j] = friction_scale * rx.dx(j);
            out.tangent[(2 * m + 1) * 6 + j] = friction_scale * ry.dx(j);
          }
      }
    out.overlap = s.diameter - dist.val();
    out.normal_force = fn.val();
    return true;
  }
} // namespace wirefem::fem
