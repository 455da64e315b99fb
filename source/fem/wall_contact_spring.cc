// The wall contact of the rod FEM under the discrete model's friction law
// (FEM/Friction law = spring, the default), with its tangent derived by
// hand; wall_contact_spring_by_ad (contact_element.cc) is the tests' oracle.
#include <wirefem/fem/contact_element.h>
#include "contact_internal.h"

#include <cmath>

namespace wirefem::fem
{
  namespace
  {
    using core::Vec2;

    /// Where a point touches the wall: the outward normal n, the overlap g
    /// and dn/dx (row a, column b: d n_a / d x_b); dg/dx is n.
    struct Touch
    {
      Vec2 n;
      double g = 0.0;
      double dn[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    };

    /// dn/dx = scale (I - n n^T).
    void project(const double scale, Touch &w)
    {
      const double n[2] = {w.n.x, w.n.y};
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          w.dn[a][b] = scale * ((a == b ? 1.0 : 0.0) - n[a] * n[b]);
    }

    /// Against a mouth's corner: n from the point towards the corner.
    void at_corner(const Vec2 &corner, const Vec2 &x, const double half_d, Touch &w)
    {
      const Vec2 d = corner - x;
      const double dc = norm(d);
      w.n = {d.x / dc, d.y / dc};
      w.g = half_d - dc;
      project(-1.0 / dc, w);
    }

    /// The circle of radius r with the radial channels' mouths.
    bool circle(const double radius, const double diameter, const bool mouths, const Vec2 &x, Touch &w)
    {
      bool in_opening;
      Vec2 corner;
      if (!detail::circle_wall_touches(radius, diameter, mouths, x, in_opening, corner))
        return false;
      if (in_opening)
        {
          at_corner(corner, x, 0.5 * diameter, w);
          return true;
        }
      const double r = norm(x);
      w.n = {x.x / r, x.y / r};
      w.g = r + 0.5 * diameter - radius;
      project(1.0 / r, w);
      return true;
    }

    /// Any other wall (ContactSettings::shaped), to first order about x.
    bool shaped(const injection::ChannelledWall &wall, const double diameter, const Vec2 &x, Touch &w)
    {
      injection::WallTouch touch;
      if (!wall.touch(x, 0.5 * diameter, touch))
        return false;
      if (touch.at_corner)
        {
          at_corner(touch.corner, x, 0.5 * diameter, w);
          return true;
        }
      const Vec2 t = core::perp(touch.towards);
      const double tv[2] = {t.x, t.y};
      w.n = touch.towards;
      w.g = touch.overlap;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          w.dn[a][b] = touch.spread * tv[a] * tv[b];
      return true;
    }
  } // namespace

  bool wall_contact_spring(const double radius, const ContactSettings &s, const double weight,
                           const double stiffness_ratio, const Vec2 &x, const Vec2 &x_old, const double dt,
                           const contact::FrictionHistory &old, ContactContribution &out,
                           SpringFriction &friction, const double friction_scale)
  {
    Touch w;
    if (!(s.shaped ? shaped(*s.shaped, s.diameter, x, w) : circle(radius, s.diameter, s.mouths, x, w)))
      return false;
    detail::start_contribution(out, 1);
    const bool want_tangent = out.want_tangent;
    const double k = s.stiffness * weight, fn = k * w.g;
    const double n[2] = {w.n.x, w.n.y};
    // The friction force ft along t = perp(n), dt/dx = R dn/dx, and its
    // derivative.
    const double t[2] = {-n[1], n[0]};
    const double dt_dx[2][2] = {{-w.dn[1][0], -w.dn[1][1]}, {w.dn[0][0], w.dn[0][1]}};
    double ft = 0.0, dft[2] = {0.0, 0.0};
    friction = SpringFriction{};
    if (s.friction)
      {
        const double kt = stiffness_ratio * k;
        const double u[2] = {x.x - x_old.x, x.y - x_old.y};
        const double slip = u[0] * t[0] + u[1] * t[1];
        const double slide = spring_step(s, kt, fn, slip, dt, old, friction);
        for (int b = 0; b < 2; ++b)
          {
            const double dslip = t[b] + u[0] * dt_dx[0][b] + u[1] * dt_dx[1][b];
            dft[b] = slide == 0.0 ? -kt * dslip : slide * k * n[b];
          }
        ft = slide == 0.0 ? -kt * (old.elongation + slip) : slide * fn;
      }
    // Residual = - force on the point: the normal force is -fn n, the
    // friction's residual -ft t.
    for (int a = 0; a < 2; ++a)
      {
        out.friction_residual[a] = -ft * t[a];
        out.residual[a] = fn * n[a] + out.friction_residual[a];
      }
    out.overlap = w.g;
    out.normal_force = fn;
    out.energy = 0.5 * k * w.g * w.g;
    if (!want_tangent)
      return true;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        {
          const double normal = k * n[b] * n[a] + fn * w.dn[a][b];
          const double tangential = -(dft[b] * t[a] + ft * dt_dx[a][b]);
          out.tangent[a * 2 + b] = normal + friction_scale * tangential;
        }
    return true;
  }
} // namespace wirefem::fem
