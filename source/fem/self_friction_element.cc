// The discrete model's friction law on a self contact of the rod FEM
// (FEM/Self friction law = spring), with its tangent derived by hand and,
// as the tests' oracle, by automatic differentiation.
#include "contact_internal.h"

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

  bool point_segment_spring_friction_by_ad(const ContactSettings &s, const double weight,
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

  namespace
  {
    /// A node against a segment: where its closest point lies (e = x2 -
    /// x1, t, dt/dx_j), the gap d = x0 - (x1 + t e) (length dist), the
    /// contact tangent tau, each point's move over the step (mx, my) and
    /// the slip vector s.
    struct NodeOnSegment
    {
      detail::ClosestParameter cp;
      double dx, dy, dist, tx, ty;
      double mx[3], my[3], sx, sy;
    };

    /// d r / dq of r_m = -share_m ft tau (m = 0, 1, 2: the node, the
    /// segment's ends; share = (1, -(1 - t), -t)) in q = (x0, y0, x1, y1,
    /// x2, y2), times friction_scale. ft is -kt (elongation + slip) while
    /// sticking (slide = 0), else slide k (D - dist).
    void spring_friction_tangent(const NodeOnSegment &g, const double k, const double kt, const double slide,
                                 const double ft, const double friction_scale, ContactContribution &out)
    {
      const Vec2 e = g.cp.e;
      const double t = g.cp.t, share[3] = {1.0, -(1.0 - t), -t};
      // d d / dq = [I, -(1 - t) I, -t I] - e (dt/dq); d s / dq = [I, -(1 - t) I,
      // -t I] + (m1 - m2) (dt/dq); n = d / |d|, dn = (I - n n^T) dd / |d|;
      // tau = (-n_y, n_x).
      const double nx = g.dx / g.dist, ny = g.dy / g.dist;
      double dt_dq[6], dft[6], dtau[2][6];
      for (int j = 0; j < 6; ++j)
        {
          dt_dq[j] = j % 2 == 0 ? g.cp.dt[j / 2].x : g.cp.dt[j / 2].y;
          const double c = share[j / 2], cx = j % 2 == 0 ? c : 0.0, cy = j % 2 == 1 ? c : 0.0;
          const double ddx = cx - e.x * dt_dq[j], ddy = cy - e.y * dt_dq[j];
          const double dsx = cx + (g.mx[1] - g.mx[2]) * dt_dq[j], dsy = cy + (g.my[1] - g.my[2]) * dt_dq[j];
          const double ddist = nx * ddx + ny * ddy;
          const double dnx = (ddx - nx * ddist) / g.dist, dny = (ddy - ny * ddist) / g.dist;
          dtau[0][j] = -dny;
          dtau[1][j] = dnx;
          const double dslip = g.tx * dsx + g.ty * dsy + g.sx * dtau[0][j] + g.sy * dtau[1][j];
          dft[j] = slide == 0.0 ? -kt * dslip : slide * (-k * ddist);
        }
      const double tau[2] = {g.tx, g.ty};
      for (int m = 0; m < 3; ++m)
        for (int a = 0; a < 2; ++a)
          for (int j = 0; j < 6; ++j)
            {
              const double dshare = m == 0 ? 0.0 : m == 1 ? dt_dq[j] : -dt_dq[j];
              out.tangent[(2 * m + a) * 6 + j] =
                  -friction_scale * (tau[a] * (ft * dshare + share[m] * dft[j]) + share[m] * ft * dtau[a][j]);
            }
    }
  } // namespace

  bool point_segment_spring_friction(const ContactSettings &s, const double weight,
                                     const double stiffness_ratio, const std::array<Vec2, 3> &x,
                                     const std::array<Vec2, 3> &x_old, const double dt,
                                     const contact::FrictionHistory &old, ContactContribution &out,
                                     SpringFriction &friction, const double friction_scale)
  {
    NodeOnSegment g;
    g.cp = detail::closest_parameter(3, x.data());
    const double t = g.cp.t;
    g.dx = x[0].x - (x[1].x + t * g.cp.e.x), g.dy = x[0].y - (x[1].y + t * g.cp.e.y);
    g.dist = std::sqrt(g.dx * g.dx + g.dy * g.dy);
    if (g.dist >= s.diameter || g.dist < 1e-12 * s.diameter)
      return false;
    detail::start_contribution(out, 3);
    const double k = s.stiffness * weight, kt = stiffness_ratio * k;
    const double fn = k * (s.diameter - g.dist);
    g.tx = -g.dy / g.dist, g.ty = g.dx / g.dist;
    // The slip: the node's move less the closest point's, along tau.
    for (int m = 0; m < 3; ++m)
      {
        g.mx[m] = x[m].x - x_old[m].x;
        g.my[m] = x[m].y - x_old[m].y;
      }
    g.sx = g.mx[0] - (1.0 - t) * g.mx[1] - t * g.mx[2], g.sy = g.my[0] - (1.0 - t) * g.my[1] - t * g.my[2];
    const double slip = g.sx * g.tx + g.sy * g.ty;
    const double slide = spring_step(s, kt, fn, slip, dt, old, friction);
    const double ft = slide == 0.0 ? -kt * (old.elongation + slip) : slide * fn;
    // Force ft tau on the node, -(1 - t) ft tau and -t ft tau on the ends.
    const double share[3] = {1.0, -(1.0 - t), -t};
    for (int m = 0; m < 3; ++m)
      {
        out.residual[2 * m] = out.friction_residual[2 * m] = -share[m] * ft * g.tx;
        out.residual[2 * m + 1] = out.friction_residual[2 * m + 1] = -share[m] * ft * g.ty;
      }
    out.overlap = s.diameter - g.dist;
    out.normal_force = fn;
    if (out.want_tangent)
      spring_friction_tangent(g, k, kt, slide, ft, friction_scale, out);
    return true;
  }
} // namespace wirefem::fem
