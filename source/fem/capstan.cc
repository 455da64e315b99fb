#include <wirefem/contact/friction_law.h>
#include <wirefem/fem/capstan.h>
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>
#include <wirefem/fem/rod_numbering.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace wirefem::fem
{
  using core::Vec2;

  CapstanSolution solve_capstan(const scene::Scene &s, double *tangent_check)
  {
    const auto &cs = s.capstan;
    const auto &w = s.wire;
    const auto &fr = s.contact.friction;
    const double diameter = 1.0;
    const double Rc = s.cavity.radius - 0.5 * diameter; // centreline on the wall
    const unsigned int p = s.fem.degree;

    // Elements of length about h over the wrap angle; the frictional
    // contacts act at the nodes, each over the wire length it stands for.
    const unsigned int n_cells =
        std::max(1u, static_cast<unsigned int>(std::lround(cs.wrap_angle * Rc / s.fem.element_length)));
    const auto shape = ElementShape::lagrange(p, cs.wrap_angle * Rc / n_cells, p);
    const double h = shape.length;
    const unsigned int n_nodes = n_cells * p + 1;
    const unsigned int n_dofs = 3 * n_nodes;
    const RodNumbering numbering{p, n_cells};
    auto global_node = [&numbering](unsigned int c, unsigned int a) { return numbering.node(c, a); };
    std::vector<double> S(n_nodes);
    for (unsigned int c = 0; c < n_cells; ++c)
      for (unsigned int a = 0; a <= p; ++a)
        S[global_node(c, a)] = (c + shape.node_position[a]) * h;
    const double length = n_cells * h;
    std::vector<double> weight(n_nodes);
    for (unsigned int k = 0; k < n_nodes; ++k)
      weight[k] = 0.5 * ((k > 0 ? S[k] - S[k - 1] : 0.0) + (k + 1 < n_nodes ? S[k + 1] - S[k] : 0.0));

    CapstanSolution out;
    out.elements = n_cells;
    out.wrap_angle = length / Rc;
    out.description =
        fmt::format("{} elements of degree {} ({}), h = {:g}", n_cells, p,
                    s.fem.formulation == scene::Formulation::kirchhoff ? "Kirchhoff" : "Reissner", h);

    SectionProperties section;
    section.EA = w.axial_stiffness;
    section.GA = s.fem.formulation == scene::Formulation::kirchhoff
                     ? s.fem.kirchhoff_penalty * w.axial_stiffness
                     : s.fem.shear_stiffness;
    const material::MomentCurvatureLaw law(w.bending_stiffness);

    const bool velocity = cs.velocity_control;
    const bool spring = s.fem.spring_friction;
    ContactSettings wall;
    wall.diameter = diameter;
    wall.stiffness = s.contact.normal_stiffness;
    wall.friction = true;
    wall.mu_static = fr.wall_static_coefficient;
    wall.mu_dynamic = fr.wall_dynamic_coefficient;
    wall.threshold_velocity = fr.threshold_velocity;
    if (spring)
      out.sliding_coefficient = wall.mu_dynamic;
    else
      {
        const double x = cs.speed / std::max(fr.threshold_velocity, 1e-9);
        out.sliding_coefficient =
            (wall.mu_dynamic + (wall.mu_static - wall.mu_dynamic) * std::exp(-x)) * std::tanh(x);
      }
    // Spring law: the friction history of each node's wall contact, as of
    // the last equilibrium, and its trial over the current step.
    std::vector<contact::FrictionHistory> history(n_nodes), trial(n_nodes);

    // The rod on the centreline circle, centred on the top of the cavity,
    // running clockwise from the clamped (pushed) end: at arc length S the
    // polar angle is a0 - S / Rc and the section angle a0 - S / Rc - pi/2.
    const double a0 = 0.5 * M_PI + 0.5 * length / Rc;
    dealii::Vector<double> u(n_dofs), u_old(n_dofs), R(n_dofs), du(n_dofs);
    auto place = [&](dealii::Vector<double> &v, const unsigned int k, const double radius,
                     const double angle) {
      v[3 * k] = radius * std::cos(angle);
      v[3 * k + 1] = radius * std::sin(angle);
      v[3 * k + 2] = angle - 0.5 * M_PI;
    };
    // Under force control nothing holds the rod but the wall: it starts
    // pressed into it by 1e-6 d (unstrained: arc length kept), so the
    // first Newton step has the wall's stiffness and finds the overlap the
    // loads call for.
    const double r_start = velocity ? Rc : Rc + 1e-6 * diameter;
    for (unsigned int k = 0; k < n_nodes; ++k)
      place(u, k, r_start, a0 - S[k] / r_start);
    const unsigned int lead = n_nodes - 1;
    const double lead_angle0 = std::atan2(u[3 * lead + 1], u[3 * lead]);

    const unsigned int nd = 3 * (p + 1);
    std::vector<unsigned int> local(nd);
    auto local_dofs = [&](unsigned int c) { numbering.cell_dofs(c, local); };
    dealii::SparsityPattern sparsity;
    numbering.make_sparsity(sparsity);
    dealii::SparseMatrix<double> K(sparsity);

    // Compression at the quadrature points (for the profile) and the axial
    // force the clamp transmits, of the last assembly.
    const dealii::QGauss<1> gauss(shape.n_q);
    std::vector<double> compression(n_cells * shape.n_q);
    std::vector<PointState> state(n_cells * shape.n_q);
    ElementResult er;
    std::vector<double> ue(nd);
    double clamp_force = 0.0, penetration = 0.0;
    // Outward unit normal at the trailing end (its section angle + pi/2).
    const auto radial = [&u]() { return Vec2{-std::sin(u[2]), std::cos(u[2])}; };

    // The trailing end is pushed along the wall. As a roller (default) it is
    // like a wire in a channel that holds its direction but not its distance
    // from the centre: its polar angle alpha and section angle are
    // prescribed, its radius is free, so the wall, not the support, carries
    // the pressure there; in its equations the node's (x, y) are rotated to
    // (radial, tangential) and the tangential row and column eliminated.
    // Clamped (Capstan/Trailing end), its radius is held too, and the clamp
    // takes the normal force of a boundary layer of length (EI/k_n)^(1/4)
    // off the wall and, with it, its friction (-0.37% of push force at k_n =
    // 2000, mu Theta = 0.38, h = 0.125).
    //
    // Under force control (spring law only) the trailing end is free and
    // pushed by a follower force P along its section, with the moment that
    // holds the wall's curvature: then no dof is prescribed.
    //
    // R = internal force - end loads at thrust T (and push P) and step dt
    // (friction velocities (u - u_old) / dt); K its Jacobian.
    const double held = w.bending_stiffness / Rc; // clockwise moment at the wall's curvature
    const auto is_fixed = [&](const unsigned int j) {
      return velocity && (j == 1 || j == 2 || (j == 0 && !cs.trailing_roller));
    };
    double push = 0.0;
    auto assemble = [&](const double thrust, const double dt, const bool want_tangent) {
      R = 0.0;
      if (want_tangent)
        K = 0.0;
      for (unsigned int c = 0; c < n_cells; ++c)
        {
          local_dofs(c);
          for (unsigned int i = 0; i < nd; ++i)
            ue[i] = u[local[i]];
          evaluate_rod_element(shape, section, law, ue.data(), &state[c * shape.n_q], 0.0, want_tangent, er);
          for (unsigned int q = 0; q < shape.n_q; ++q)
            compression[c * shape.n_q + q] = -section.EA * er.state[q].axial_strain;
          for (unsigned int i = 0; i < nd; ++i)
            {
              R[local[i]] += er.residual[i];
              if (want_tangent)
                for (unsigned int j = 0; j < nd; ++j)
                  K.add(local[i], local[j], er.tangent[i * nd + j]);
            }
        }
      penetration = 0.0;
      ContactContribution cc;
      for (unsigned int k = (cs.trailing_roller || !velocity) ? 0 : 1; k < n_nodes; ++k)
        {
          const Vec2 x{u[3 * k], u[3 * k + 1]};
          const Vec2 xo{u_old[3 * k], u_old[3 * k + 1]};
          bool touching;
          if (spring)
            {
              SpringFriction sf;
              touching = wall_contact_spring(s.cavity.radius, wall, weight[k], fr.tangential_stiffness_ratio,
                                             x, xo, dt, history[k], cc, sf);
              trial[k] = touching ? sf.history : contact::FrictionHistory{};
            }
          else
            touching = wall_contact(s.cavity.radius, wall, weight[k], x, (-1.0 / dt) * xo, 1.0 / dt, cc);
          if (!touching)
            continue;
          penetration = std::max(penetration, cc.overlap / diameter);
          for (unsigned int i = 0; i < 2; ++i)
            {
              R[3 * k + i] += cc.residual[i];
              if (want_tangent)
                for (unsigned int j = 0; j < 2; ++j)
                  K.add(3 * k + i, 3 * k + j, cc.tangent[2 * i + j]);
            }
        }
      // A follower force -f (cos theta, sin theta) along the section at
      // node k, with its derivative with respect to the section angle.
      const auto follower = [&](const unsigned int k, const double f) {
        const double th = u[3 * k + 2];
        R[3 * k] += f * std::cos(th);
        R[3 * k + 1] += f * std::sin(th);
        if (want_tangent)
          {
            K.add(3 * k, 3 * k + 2, -f * std::sin(th));
            K.add(3 * k + 1, 3 * k + 2, f * std::cos(th));
          }
      };
      // Leading end: the compressive follower force T and the clockwise
      // moment that holds the wall's curvature.
      follower(lead, thrust);
      R[3 * lead + 2] += held;
      if (!velocity)
        {
          // Trailing end: the push P along its section and the moment.
          follower(0, -push);
          R[2] -= held;
          clamp_force = push;
          return R.linfty_norm();
        }
      // The support's reaction along the section (the wall tangent) at the
      // trailing end is the axial force it transmits (compression positive).
      const Vec2 er = radial();
      clamp_force = R[0] * er.y - R[1] * er.x;
      R[0] = cs.trailing_roller ? R[0] * er.x + R[1] * er.y : 0.0;
      R[1] = R[2] = 0.0;
      if (want_tangent)
        {
          if (cs.trailing_roller)
            {
              local_dofs(0);
              for (const auto j : local)
                K.set(0, j, er.x * K.el(0, j) + er.y * K.el(1, j));
              for (const auto i : local)
                K.set(i, 0, er.x * K.el(i, 0) + er.y * K.el(i, 1));
            }
          else
            fix_dof(K, 0);
          fix_dof(K, 1);
          fix_dof(K, 2);
        }
      return R.linfty_norm();
    };

    // The assembled tangent against central differences of the residual
    // (free dofs and the trailing end's radius): max |K - K_fd| / max |K|.
    auto check_tangent = [&](const double thrust, const double dt) {
      assemble(thrust, dt, true);
      const Vec2 er = radial();
      const double eps = 1e-7;
      double worst = 0.0, largest = 0.0;
      dealii::Vector<double> rp(n_dofs), u0 = u;
      for (unsigned int j = 0; j < n_dofs; ++j)
        {
          if (is_fixed(j))
            continue;
          for (const double sign : {1.0, -1.0})
            {
              u = u0;
              if (j == 0 && velocity)
                u[0] += sign * eps * er.x, u[1] += sign * eps * er.y;
              else
                u[j] += sign * eps;
              assemble(thrust, dt, false);
              if (sign > 0.0)
                rp = R;
              else
                rp -= R;
            }
          for (unsigned int i = 0; i < n_dofs; ++i)
            {
              if (is_fixed(i) || !sparsity.exists(i, j))
                continue;
              worst = std::max(worst, std::abs(K.el(i, j) - rp[i] / (2.0 * eps)));
              largest = std::max(largest, std::abs(K.el(i, j)));
            }
        }
      u = u0;
      return worst / largest;
    };

    const double tol = s.fem.newton_tolerance * cs.end_force;
    auto newton = [&](const double thrust, const double dt) {
      for (unsigned int it = 0; it < s.fem.maximum_iterations; ++it)
        {
          if (tangent_check && it == 1 && out.steps == 0)
            *tangent_check = check_tangent(thrust, dt);
          const double r = assemble(thrust, dt, true);
          if (!std::isfinite(r))
            return false;
          if (r < tol)
            return true;
          dealii::SparseDirectUMFPACK solver;
          solver.initialize(K);
          solver.vmult(du, R);
          if (velocity)
            {
              // du[0] is the radial correction of the trailing end.
              const Vec2 er = radial();
              const double dr = du[0];
              du[0] = dr * er.x;
              du[1] = dr * er.y;
            }
          u -= du;
          ++out.newton_iterations;
        }
      return assemble(thrust, dt, false) < tol;
    };

    const double t_end = velocity ? cs.slide_time() : cs.maximum_time;
    const double t_average = 0.5 * (cs.ramp_time + t_end);
    // A step moves the clamp by at most a fifth of a node spacing.
    const double node_spacing = h / p;
    // Under force control a step raises the push by at most 1% of T0.
    double dt_max = s.fem.time_step > 0.0 ? s.fem.time_step
                    : velocity            ? 0.2 * node_spacing / cs.speed
                                          : 0.01 / cs.force_rate;
    if (cs.ramp_time > 0.0)
      dt_max = std::min(dt_max, 0.05 * cs.ramp_time);
    out.time_step = dt_max;

    double t = 0.0, force_sum = 0.0, force_time = 0.0;
    std::vector<double> profile_sum(compression.size(), 0.0);
    // No solve of the unloaded rod: it touches the wall with zero force,
    // where the penalty's active set has no unique answer. From the first
    // step on the thrust presses it on.
    double dt = dt_max;
    while (t < t_end - 1e-12 * t_end)
      {
        const double t1 = std::min(t + dt, t_end);
        const double step = t1 - t;
        u_old = u;
        if (velocity)
          {
            // Predictor: the whole rod slides with the clamp.
            const double dpsi = (cs.pushed(t1) - cs.pushed(t)) / Rc;
            for (unsigned int k = 0; k < n_nodes; ++k)
              {
                const double x = u[3 * k], y = u[3 * k + 1];
                u[3 * k] = std::cos(dpsi) * x + std::sin(dpsi) * y;
                u[3 * k + 1] = -std::sin(dpsi) * x + std::cos(dpsi) * y;
                u[3 * k + 2] -= dpsi;
              }
            place(u, 0, std::hypot(u[0], u[1]), a0 - cs.pushed(t1) / Rc);
          }
        const double ramp = cs.ramp_time > 0.0 ? std::min(1.0, t1 / cs.ramp_time) : 1.0;
        const double thrust = cs.end_force * ramp;
        push = cs.end_force * (ramp + cs.force_rate * std::max(0.0, t1 - cs.ramp_time));
        if (!newton(thrust, step))
          {
            u = u_old;
            dt *= 0.5;
            ++out.step_cuts;
            if (dt < s.fem.minimum_time_step)
              {
                // Under force control: no equilibrium at any larger push,
                // so the wire slips at the last one that had one.
                if (!velocity && out.steps > 0 && t > cs.ramp_time)
                  {
                    out.finished = out.onset_without_equilibrium = true;
                    out.onset_force = out.series.back()[3];
                  }
                out.time = t;
                return out;
              }
            continue;
          }
        history = trial;
        t = t1;
        ++out.steps;
        dt = std::min(dt_max, 2.0 * dt);
        out.push_force_peak = std::max(out.push_force_peak, clamp_force);
        out.max_penetration = std::max(out.max_penetration, penetration);
        if (t > t_average)
          {
            force_sum += clamp_force * step;
            force_time += step;
            for (std::size_t i = 0; i < compression.size(); ++i)
              profile_sum[i] += compression[i] * step;
          }
        const double lead_slide = Rc * (lead_angle0 - std::atan2(u[3 * lead + 1], u[3 * lead]));
        out.series.push_back({{t, velocity ? cs.pushed(t) : 0.0, lead_slide, clamp_force, compression[0]}});
        if (!velocity && lead_slide >= cs.slip_distance)
          {
            out.finished = true;
            out.onset_force = push;
            out.time = t;
            return out;
          }
      }
    out.time = t;
    if (!velocity)
      return out; // force control that never slipped: not finished
    out.finished = force_time > 0.0;
    if (out.finished)
      out.push_force = force_sum / force_time;
    for (unsigned int c = 0; c < n_cells; ++c)
      for (unsigned int q = 0; q < shape.n_q; ++q)
        {
          const double Sq = (c + gauss.point(q)[0]) * h;
          const std::size_t i = c * shape.n_q + q;
          out.profile.push_back(
              {{(length - Sq) / Rc, force_time > 0.0 ? profile_sum[i] / force_time : compression[i]}});
        }
    return out;
  }
} // namespace wirefem::fem
