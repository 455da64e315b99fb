#include <wirefem/contact/segment_distance.h>
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>
#include "contact_internal.h"

#include <vector>

#include <Sacado.hpp>
#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <cmath>

namespace wirefem::fem
{
  namespace
  {
    using Fad = Sacado::Fad::SLFad<double, 6>; // at most 6 coordinates: no heap
    using core::Vec2;

    template <typename T>
    struct P
    {
      T x, y;
    };

    /// Friction force magnitude along the tangent for a tangential velocity
    /// vt and normal force fn (regularised Coulomb, static to dynamic).
    template <typename T>
    T friction_force(const ContactSettings &s, const T &fn, const T &vt)
    {
      using std::abs;
      using std::exp;
      using std::tanh;
      const double vth = regularised_threshold(s);
      const T mu = s.mu_dynamic + (s.mu_static - s.mu_dynamic) * exp(-abs(vt) / vth);
      return -mu * fn * tanh(vt / vth);
    }

    void to_dense(const int n_dofs, const Fad *r, const Fad *rf, const double friction_scale,
                  ContactContribution &out)
    {
      for (int i = 0; i < n_dofs; ++i)
        {
          out.residual[i] = r[i].val();
          out.friction_residual[i] = rf[i].val();
          for (int j = 0; j < n_dofs; ++j)
            out.tangent[i * n_dofs + j] = r[i].dx(j) + (friction_scale - 1.0) * rf[i].dx(j);
        }
    }
  } // namespace

  double sliding_coefficient(const ContactSettings &s, const double v)
  {
    return -friction_force<double>(s, 1.0, v);
  }

  namespace
  {
    /// A point (px, py) against a mouth's corner: n from the point towards
    /// the corner (the corner pushes along -n) and the overlap g.
    void corner_geometry(const Vec2 &corner, const Fad &px, const Fad &py, const double half_d, Fad &nx,
                         Fad &ny, Fad &g)
    {
      const Fad dx = corner.x - px, dy = corner.y - py;
      const Fad dc = sqrt(dx * dx + dy * dy);
      nx = dx / dc;
      ny = dy / dc;
      g = half_d - dc;
    }

    /// The outward normal n and the overlap g at x for any wall
    /// (ContactSettings::shaped), to first order about x: the overlap grows
    /// along n, which turns along the wall's tangent t as
    /// d n / dx = spread t t^T; at a mouth's corner, as wall_geometry's.
    bool shaped_wall_geometry(const injection::ChannelledWall &wall, const double diameter, const Vec2 &x,
                              Fad &nx, Fad &ny, Fad &g)
    {
      injection::WallTouch touch;
      if (!wall.touch(x, 0.5 * diameter, touch))
        return false;
      const Fad px(2, 0, x.x), py(2, 1, x.y);
      if (touch.at_corner)
        {
          corner_geometry(touch.corner, px, py, 0.5 * diameter, nx, ny, g);
          return true;
        }
      const Vec2 n = touch.towards, t = core::perp(n);
      const Fad ex = px - x.x, ey = py - x.y; // zero, with unit derivatives
      const Fad along = touch.spread * (t.x * ex + t.y * ey);
      nx = n.x + along * t.x;
      ny = n.y + along * t.y;
      g = touch.overlap + n.x * ex + n.y * ey;
      return true;
    }

    /// The wall's outward normal n at x and the overlap g, with their
    /// derivatives with respect to x: the circle, or within an opening the
    /// corner of the mouth. Returns false when x does not touch.
    bool wall_geometry(const double radius, const double diameter, const bool mouths, const Vec2 &x, Fad &nx,
                       Fad &ny, Fad &g)
    {
      const double half_d = 0.5 * diameter;
      bool in_opening;
      Vec2 corner;
      if (!detail::circle_wall_touches(radius, diameter, mouths, x, in_opening, corner))
        return false;
      const Fad px(2, 0, x.x), py(2, 1, x.y);
      if (in_opening)
        corner_geometry(corner, px, py, half_d, nx, ny, g);
      else
        {
          const Fad r = sqrt(px * px + py * py);
          nx = px / r;
          ny = py / r;
          g = r + half_d - radius;
        }
      return true;
    }
  } // namespace

  namespace
  {
    /// A point touching the wall: its coordinates, the wall's normal and
    /// tangent there, the overlap and the normal force, with derivatives.
    struct WallPoint
    {
      Fad px, py, nx, ny, g, fn;
      double k = 0.0; ///< penalty k w
    };

    bool wall_point(const double radius, const ContactSettings &s, const double weight, const Vec2 &x,
                    WallPoint &w)
    {
      if (!(s.shaped ? shaped_wall_geometry(*s.shaped, s.diameter, x, w.nx, w.ny, w.g)
                     : wall_geometry(radius, s.diameter, s.mouths, x, w.nx, w.ny, w.g)))
        return false;
      w.px = Fad(2, 0, x.x);
      w.py = Fad(2, 1, x.y);
      w.k = s.stiffness * weight;
      w.fn = w.k * w.g;
      return true;
    }

    /// The contribution of the normal penalty plus the friction residual rf.
    void finish_wall(const WallPoint &w, const Fad *rf, const double friction_scale, ContactContribution &out)
    {
      // Residual = - force on the point; the normal force is -fn n.
      const Fad r[2] = {w.fn * w.nx + rf[0], w.fn * w.ny + rf[1]};
      out = ContactContribution{};
      out.n_points = 1;
      out.overlap = w.g.val();
      out.normal_force = w.fn.val();
      out.energy = 0.5 * w.k * w.g.val() * w.g.val();
      to_dense(2, r, rf, friction_scale, out);
    }
  } // namespace

  bool wall_contact(const double radius, const ContactSettings &s, const double weight, const Vec2 &x,
                    const Vec2 &v0, const double c, ContactContribution &out, const double friction_scale)
  {
    WallPoint w;
    if (!wall_point(radius, s, weight, x, w))
      return false;
    Fad rf[2] = {0.0, 0.0};
    if (s.friction)
      {
        const Fad tx = -w.ny, ty = w.nx;
        const Fad vx = c * w.px + v0.x, vy = c * w.py + v0.y;
        const Fad ft = friction_force<Fad>(s, w.fn, Fad(vx * tx + vy * ty));
        rf[0] = -ft * tx;
        rf[1] = -ft * ty;
      }
    finish_wall(w, rf, friction_scale, out);
    return true;
  }

  double spring_step(const ContactSettings &s, const double kt, const double fn, const double slip,
                     const double dt, const contact::FrictionHistory &old, SpringFriction &friction)
  {
    friction = SpringFriction{};
    const double limit = (old.sliding ? s.mu_dynamic : s.mu_static) * fn;
    const double trial = old.elongation + slip;
    double ft = -kt * trial, slide = 0.0;
    friction.history.elongation = trial;
    if (std::abs(ft) > limit)
      {
        slide = (ft > 0.0 ? 1.0 : -1.0) * s.mu_dynamic;
        ft = slide * fn;
        friction.history.elongation = -ft / kt;
        friction.history.sliding = std::abs(slip) >= s.threshold_velocity * dt;
      }
    friction.dissipated =
        0.5 * (kt * old.elongation - ft) * slip -
        0.5 * kt *
            (friction.history.elongation * friction.history.elongation - old.elongation * old.elongation);
    friction.stored = 0.5 * kt * friction.history.elongation * friction.history.elongation;
    return slide;
  }

  bool wall_contact_spring_by_ad(const double radius, const ContactSettings &s, const double weight,
                                 const double stiffness_ratio, const Vec2 &x, const Vec2 &x_old,
                                 const double dt, const contact::FrictionHistory &old,
                                 ContactContribution &out, SpringFriction &friction,
                                 const double friction_scale)
  {
    WallPoint w;
    if (!wall_point(radius, s, weight, x, w))
      return false;
    friction = SpringFriction{};
    Fad rf[2] = {0.0, 0.0};
    if (s.friction)
      {
        const double kt = stiffness_ratio * w.k;
        const Fad tx = -w.ny, ty = w.nx;
        // The relative tangential displacement over the step (the wall is fixed).
        const Fad slip = (w.px - x_old.x) * tx + (w.py - x_old.y) * ty;
        // The cap of the step is set by the state the step starts from
        // (sliding means: slid at v_th or faster over the last step), so
        // within Newton's iterations the law is a fixed return map with one
        // kink.
        const double slide = spring_step(s, kt, w.fn.val(), slip.val(), dt, old, friction);
        const Fad ft = slide == 0.0 ? Fad(-kt * (old.elongation + slip)) : Fad(slide * w.fn);
        rf[0] = -ft * tx;
        rf[1] = -ft * ty;
      }
    finish_wall(w, rf, friction_scale, out);
    return true;
  }

  bool segment_contact(const ContactSettings &s, const double weight, const std::array<Vec2, 4> &x,
                       const std::array<Vec2, 4> &v0, const double c, ContactContribution &out,
                       const double friction_scale)
  {
    const auto cp = contact::closest_points(x[0], x[1], x[2], x[3]);
    if (cp.distance >= s.diameter)
      return false;
    out = ContactContribution{};
    out.n_points = 4;
    out.overlap = s.diameter - cp.distance;
    if (cp.distance < 1e-12 * s.diameter)
      return false; // crossing centrelines: no normal (reported through the overlap)

    // The end point and the segment of the closest pair.
    int point, s0, s1;
    if (cp.s <= 0.0 || cp.s >= 1.0)
      point = cp.s <= 0.0 ? 0 : 1, s0 = 2, s1 = 3;
    else if (cp.t <= 0.0 || cp.t >= 1.0)
      point = cp.t <= 0.0 ? 2 : 3, s0 = 0, s1 = 1;
    else
      return false; // both interior: the centrelines cross

    const std::array<Vec2, 3> xp{{x[point], x[s0], x[s1]}};
    const std::array<Vec2, 3> vp{{v0[point], v0[s0], v0[s1]}};
    ContactContribution pc;
    double t;
    if (!point_segment_contact(s, weight, xp, vp, c, pc, t, friction_scale))
      return false;
    const int ids[3] = {point, s0, s1};
    for (int m = 0; m < 3; ++m)
      for (int cm = 0; cm < 2; ++cm)
        {
          out.residual[2 * ids[m] + cm] = pc.residual[2 * m + cm];
          out.friction_residual[2 * ids[m] + cm] = pc.friction_residual[2 * m + cm];
          for (int n = 0; n < 3; ++n)
            for (int cn = 0; cn < 2; ++cn)
              out.tangent[(2 * ids[m] + cm) * 8 + 2 * ids[n] + cn] =
                  pc.tangent[(2 * m + cm) * 6 + 2 * n + cn];
        }
    out.normal_force = pc.normal_force;
    out.energy = pc.energy;
    return true;
  }

  namespace
  {
    /// Point x[0] against the segment x[1]-x[2] (n = 3) or the point x[1]
    /// (n = 2): penalty on the overlap with the closest point q, regularised
    /// friction on the relative velocity of x[0] and q.
    bool point_contact_by_ad(const ContactSettings &s, const double weight, const int n, const Vec2 *x,
                             const Vec2 *v0, const double c, ContactContribution &out, double &t_out,
                             const double friction_scale)
    {
      const int nd = detail::start_contribution(out, n);
      P<Fad> p[3];
      for (int m = 0; m < n; ++m)
        p[m] = {Fad(nd, 2 * m, x[m].x), Fad(nd, 2 * m + 1, x[m].y)};
      Fad t = 0.0, dx = 0.0, dy = 0.0;
      if (n == 3)
        {
          dx = p[2].x - p[1].x, dy = p[2].y - p[1].y;
          t = ((p[0].x - p[1].x) * dx + (p[0].y - p[1].y) * dy) / (dx * dx + dy * dy);
          if (t.val() <= 0.0)
            t = 0.0;
          else if (t.val() >= 1.0)
            t = 1.0;
        }
      t_out = t.val();
      const Fad qx = p[1].x + t * dx, qy = p[1].y + t * dy;
      const Fad ex = p[0].x - qx, ey = p[0].y - qy;
      const Fad dist = sqrt(ex * ex + ey * ey);
      if (dist.val() >= s.diameter)
        return false;
      out.overlap = s.diameter - dist.val();
      if (dist.val() < 1e-12 * s.diameter)
        return false;
      const Fad nx = ex / dist, ny = ey / dist; // from q towards the point
      const double k = s.stiffness * weight;
      const Fad g = s.diameter - dist;
      const Fad fn = k * g;
      // Force on the point +fn n, on the segment ends -(1-t) fn n and -t fn n
      // (on x[1] -fn n when it is a point).
      const Fad fx = fn * nx, fy = fn * ny;
      Fad ffx = 0.0, ffy = 0.0;
      if (s.friction)
        {
          const auto vel = [&](const int m, const bool y) -> Fad {
            return c * (y ? p[m].y : p[m].x) + (y ? v0[m].y : v0[m].x);
          };
          const Fad tx = -ny, ty = nx;
          Fad vqx = vel(1, false), vqy = vel(1, true);
          if (n == 3)
            {
              vqx = (1.0 - t) * vqx + t * vel(2, false);
              vqy = (1.0 - t) * vqy + t * vel(2, true);
            }
          const Fad ft =
              friction_force<Fad>(s, fn, Fad((vel(0, false) - vqx) * tx + (vel(0, true) - vqy) * ty));
          ffx = ft * tx;
          ffy = ft * ty;
        }
      const Fad share[3] = {Fad(1.0), n == 3 ? Fad(-(1.0 - t)) : Fad(-1.0), -t};
      for (int m = 0; m < n; ++m)
        {
          const Fad rfx = -share[m] * ffx, rfy = -share[m] * ffy;
          const Fad rx = -share[m] * fx + rfx, ry = -share[m] * fy + rfy;
          out.residual[2 * m] = rx.val();
          out.residual[2 * m + 1] = ry.val();
          out.friction_residual[2 * m] = rfx.val();
          out.friction_residual[2 * m + 1] = rfy.val();
          for (int j = 0; j < nd; ++j)
            {
              out.tangent[(2 * m) * nd + j] = rx.dx(j) + (friction_scale - 1.0) * rfx.dx(j);
              out.tangent[(2 * m + 1) * nd + j] = ry.dx(j) + (friction_scale - 1.0) * rfy.dx(j);
            }
        }
      out.normal_force = fn.val();
      out.energy = 0.5 * k * g.val() * g.val();
      return true;
    }
  } // namespace

  namespace
  {
    /// Whether x[0] is farther than d from the segment x[1]-x[2] (n == 3) or the point x[1]
    /// (n == 2) by 1e-12 d^2, from the squared distance (no square root; t: as closest_parameter's).
    bool clearly_apart(const double d, const int n, const Vec2 *x, double &t)
    {
      const double far = d * d * (1.0 + 1e-12);
      t = 0.0;
      if (n != 3)
        return core::norm_square(x[0] - x[1]) > far;
      const contact::PointOnSegment c = contact::closest_on_segment(x[0], x[1], x[2]);
      t = c.t;
      return c.distance2 > far;
    }

    /// A point that does not touch (most candidates): no need to clear the rest of out.
    bool apart(ContactContribution &out, const int n)
    {
      out.n_points = n;
      out.overlap = 0.0;
      return false;
    }

    /// The friction force of a point contact, f_t = friction(f_n, v_t) with
    /// v_t = tau . sum_m share_m v_m and v_m = c x_m + v0_m, its two partial
    /// derivatives, and the velocities its tangent needs.
    struct PointFriction
    {
      double ft = 0.0, dft_dfn = 0.0, dft_dvt = 0.0;
      Vec2 vrel{0.0, 0.0}, v1{0.0, 0.0}, v2{0.0, 0.0};
    };

    PointFriction point_friction(const ContactSettings &s, const int n, const Vec2 *x, const Vec2 *v0,
                                 const double c, const double *share, const Vec2 &tau, const double fn)
    {
      PointFriction pf;
      if (!s.friction)
        return pf;
      for (int m = 0; m < n; ++m)
        pf.vrel = pf.vrel + share[m] * (c * x[m] + v0[m]);
      if (n == 3)
        pf.v1 = c * x[1] + v0[1], pf.v2 = c * x[2] + v0[2];
      // The law and its two partial derivatives from its one definition.
      using Fad2 = Sacado::Fad::SFad<double, 2>;
      const Fad2 f = friction_force<Fad2>(s, Fad2(2, 0, fn), Fad2(2, 1, dot(pf.vrel, tau)));
      pf.ft = f.val();
      pf.dft_dfn = f.dx(0);
      pf.dft_dvt = f.dx(1);
      return pf;
    }

    /// point_contact_by_ad with the derivatives by hand. With share
    /// (1, -(1 - t), -t) (or (1, -1) against a point), d = x0 - q = sum_m
    /// share_m x_m, n = d / |d|, g = D - |d|, f_n = k g, the residual is
    /// r_m = -share_m (f_n n + f_t tau), tau = R n (R: +90 degrees), and
    ///   d share_1 = dt, d share_2 = -dt (interior t; 0 when clamped),
    ///   d f_n / d x_j = -k share_j n, d n / d x_j = (share_j P - e dt_j^T) / |d|,
    ///   P = I - n n^T, e = x2 - x1 (n is normal to e at an interior t),
    ///   dt/dx0 = e / |e|^2, dt/dx2 = (w - 2 t e) / |e|^2, dt/dx1 = -(dt/dx0 + dt/dx2), w = x0 - x1.
    bool point_contact(const ContactSettings &s, const double weight, const int n, const Vec2 *x,
                       const Vec2 *v0, const double c, ContactContribution &out, double &t_out,
                       const double friction_scale)
    {
      if (clearly_apart(s.diameter, n, x, t_out))
        return apart(out, n);
      const detail::ClosestParameter cp = detail::closest_parameter(n, x);
      const Vec2 e = cp.e;
      const double t = cp.t;
      const std::array<Vec2, 3> &dt = cp.dt; // dt / dx_j
      t_out = t;
      const Vec2 q = x[1] + t * e;
      const Vec2 d = x[0] - q;
      const double dist = norm(d);
      if (dist >= s.diameter)
        return apart(out, n);
      const int nd = detail::start_contribution(out, n);
      out.overlap = s.diameter - dist;
      if (dist < 1e-12 * s.diameter)
        return false;
      const Vec2 nn = (1.0 / dist) * d;
      const Vec2 tau{-nn.y, nn.x};
      const double k = s.stiffness * weight, g = s.diameter - dist, fn = k * g;
      const double share[3] = {1.0, n == 3 ? -(1.0 - t) : -1.0, -t};
      const double dshare[3] = {0.0, 1.0, -1.0}; // times dt
      // d n_a / d x_{j,b}, a and b the components.
      const auto dn = [&](const int j, const int a, const int b) {
        const double P = (a == b ? 1.0 : 0.0) - (a ? nn.y : nn.x) * (b ? nn.y : nn.x);
        return (share[j] * P - (a ? e.y : e.x) * (b ? dt[j].y : dt[j].x)) / dist;
      };
      const auto comp = [](const Vec2 &v, const int a) { return a ? v.y : v.x; };
      // Friction: f_t = friction(f_n, v_t), v_t = tau . sum_m share_m v_m, v_m = c x_m + v0_m.
      const PointFriction pf = point_friction(s, n, x, v0, c, share, tau, fn);
      const double ft = pf.ft, dft_dfn = pf.dft_dfn, dft_dvt = pf.dft_dvt;
      const Vec2 vrel = pf.vrel, v1 = pf.v1, v2 = pf.v2;
      for (int m = 0; m < n; ++m)
        for (int a = 0; a < 2; ++a)
          {
            const double rf = -share[m] * ft * comp(tau, a);
            out.friction_residual[2 * m + a] = rf;
            out.residual[2 * m + a] = -share[m] * fn * comp(nn, a) + rf;
          }
      out.normal_force = fn;
      out.energy = 0.5 * k * g * g;
      if (!out.want_tangent)
        return true;
      for (int j = 0; j < n; ++j)
        for (int b = 0; b < 2; ++b)
          {
            const int col = 2 * j + b;
            const double dfn = -k * share[j] * comp(nn, b);
            const double dtj = comp(dt[j], b);
            const double dnj[2] = {dn(j, 0, b), dn(j, 1, b)};
            // d tau = R d n: d tau_x = -d n_y, d tau_y = d n_x.
            const double dtau[2] = {-dnj[1], dnj[0]};
            double dft = 0.0;
            if (s.friction)
              {
                // d v_rel / d x_{j,b} = c share_j e_b + (v1 - v2) dt_j,b
                const Vec2 dv =
                    Vec2{b == 0 ? c * share[j] : 0.0, b == 1 ? c * share[j] : 0.0} + dtj * (v1 - v2);
                const double dvt = dot(dv, tau) + vrel.x * dtau[0] + vrel.y * dtau[1];
                dft = dft_dfn * dfn + dft_dvt * dvt;
              }
            for (int m = 0; m < n; ++m)
              for (int a = 0; a < 2; ++a)
                {
                  const double ds = dshare[m] * dtj;
                  const double normal =
                      -(ds * fn * comp(nn, a) + share[m] * dfn * comp(nn, a) + share[m] * fn * dnj[a]);
                  const double friction =
                      -(ds * ft * comp(tau, a) + share[m] * dft * comp(tau, a) + share[m] * ft * dtau[a]);
                  out.tangent[(2 * m + a) * nd + col] = normal + friction_scale * friction;
                }
          }
      return true;
    }
  } // namespace

  bool point_segment_contact(const ContactSettings &s, const double weight, const std::array<Vec2, 3> &x,
                             const std::array<Vec2, 3> &v0, const double c, ContactContribution &out,
                             double &t_out, const double friction_scale)
  {
    return point_contact(s, weight, 3, x.data(), v0.data(), c, out, t_out, friction_scale);
  }

  bool point_segment_contact_by_ad(const ContactSettings &s, const double weight,
                                   const std::array<Vec2, 3> &x, const std::array<Vec2, 3> &v0,
                                   const double c, ContactContribution &out, double &t_out,
                                   const double friction_scale)
  {
    return point_contact_by_ad(s, weight, 3, x.data(), v0.data(), c, out, t_out, friction_scale);
  }

  bool point_point_contact(const ContactSettings &s, const double weight, const std::array<Vec2, 2> &x,
                           const std::array<Vec2, 2> &v0, const double c, ContactContribution &out,
                           const double friction_scale)
  {
    double t;
    return point_contact(s, weight, 2, x.data(), v0.data(), c, out, t, friction_scale);
  }

  bool point_stretch_contact(const ContactSettings &s, const double weight, const std::array<Vec2, 3> &x,
                             const std::array<Vec2, 3> &v0, const double c, const bool next_presses,
                             ContactContribution &out, double &t, double &vertex_force,
                             const double friction_scale)
  {
    vertex_force = 0.0;
    if (!point_segment_contact(s, weight, x, v0, c, out, t, friction_scale))
      return false;
    ContactContribution vc;
    vc.want_tangent = out.want_tangent;
    if (!next_presses ||
        !point_point_contact(s, weight, {{x[0], x[2]}}, {{v0[0], v0[2]}}, c, vc, friction_scale))
      return true;
    // vc acts on points 0 and 2 of out.
    const int ids[2] = {0, 2};
    for (int m = 0; m < 2; ++m)
      for (int cm = 0; cm < 2; ++cm)
        {
          const int i = 2 * ids[m] + cm;
          out.residual[i] -= vc.residual[2 * m + cm];
          out.friction_residual[i] -= vc.friction_residual[2 * m + cm];
          for (int n = 0; n < 2 && out.want_tangent; ++n)
            for (int cn = 0; cn < 2; ++cn)
              out.tangent[i * 6 + 2 * ids[n] + cn] -= vc.tangent[(2 * m + cm) * 4 + 2 * n + cn];
        }
    out.energy -= vc.energy;
    vertex_force = vc.normal_force;
    return true;
  }
} // namespace wirefem::fem
