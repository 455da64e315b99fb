// The capstan loading of the rod FEM (Set-up = capstan): a rod on the wall of
// the cavity over a wrap angle, pushed along it against a compressive
// follower force on its leading end. Its steps are the quasi-static steps of
// the one Newton solver (rod_stepper.cc).
#include "rod_model_impl.h"

#include <deal.II/base/quadrature_lib.h>

namespace wirefem::fem
{
  void RodModel::Impl::build_capstan_mesh(const scene::RodScene &s)
  {
    // Elements of length about h over the wrap angle; the frictional
    // contacts act at the nodes, each over the wire length it stands for.
    const auto &cs = s.capstan;
    cap.Rc = radius - 0.5 * diameter; // the centreline on the wall
    n_cells =
        std::max(1u, static_cast<unsigned int>(std::lround(cs.wrap_angle * cap.Rc / s.fem.element_length)));
    h = cs.wrap_angle * cap.Rc / n_cells;
    a_left = 0.0;
    a_right = n_cells * h;
    cap.velocity = cs.velocity_control;
    cap.roller = cs.trailing_roller;
    cap.held = s.wire.bending_stiffness / cap.Rc; // clockwise
    cap.a0 = 0.5 * M_PI + 0.5 * a_right / cap.Rc;
    cap.t_end = cap.velocity ? cs.slide_time() : cs.maximum_time;
  }

  void RodModel::Impl::set_capstan_state()
  {
    // On the centreline circle, centred on the top of the cavity, running
    // clockwise from the trailing end: at arc length S the polar angle is
    // a0 - S / Rc and the section angle that minus pi/2. Under force control
    // nothing holds the rod but the wall: it starts pressed into it by 1e-6 d
    // (unstrained: arc length kept), so that the first Newton step has the
    // wall's stiffness and finds the overlap the loads call for.
    const double r_start = cap.velocity ? cap.Rc : cap.Rc + 1e-6 * diameter;
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        const double angle = cap.a0 - node_S[k] / r_start;
        u[3 * k] = r_start * std::cos(angle);
        u[3 * k + 1] = r_start * std::sin(angle);
        u[3 * k + 2] = angle - 0.5 * M_PI;
      }
    const unsigned int lead = n_nodes - 1;
    cap.lead_angle0 = std::atan2(u[3 * lead + 1], u[3 * lead]);
  }

  void RodModel::Impl::assemble_capstan_loads(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    // A follower force -f (cos theta, sin theta) along the section at node
    // k, with its derivative with respect to the section angle.
    const auto follower = [&](const unsigned int k, const double f) {
      const double th = u1[3 * k + 2];
      e.residual[3 * k] += f * std::cos(th);
      e.residual[3 * k + 1] += f * std::sin(th);
      if (rq.want_tangent)
        {
          const double m[9] = {0, 0, -f * std::sin(th), 0, 0, f * std::cos(th), 0, 0, 0};
          const int g[3] = {node_dof(k, 0), node_dof(k, 1), node_dof(k, 2)};
          add_matrix(rq, g, 3, m, rq.c_force);
        }
    };
    // Leading end: the compressive follower force and the clockwise moment
    // that holds the wall's curvature.
    const unsigned int lead = n_nodes - 1;
    follower(lead, scene.capstan.end_force_at(wall_time));
    e.residual[3 * lead + 2] += cap.held;
    if (!cap.velocity)
      {
        // Trailing end: the push along its section and the moment.
        const double push = scene.capstan.push_force_at(wall_time);
        follower(0, -push);
        e.residual[2] -= cap.held;
        e.push_force = push;
      }
  }

  void RodModel::Impl::constrain_trailing_end(const AssemblyRequest &rq, Evaluation &e)
  {
    if (!cap.velocity)
      return;
    // The support's reaction along the section (the wall tangent) at the
    // trailing end is the axial force it transmits (compression positive).
    const auto &u1 = *rq.u;
    const Vec2 er{-std::sin(u1[2]), std::cos(u1[2])}; // outward normal
    e.push_force = e.residual[0] * er.y - e.residual[1] * er.x;
    if (!cap.roller || !rq.constrain)
      return; // held: node 0 is prescribed
    e.residual[0] = e.residual[0] * er.x + e.residual[1] * er.y;
    e.residual[1] = e.residual[2] = 0.0;
    if (!rq.want_tangent)
      return;
    // K's dofs start at node 0 here (the free range starts there): rows 0
    // and 1 (and columns) have the same pattern, node 0's elements.
    const std::vector<int> cols(K.columns().begin() + K.row_start()[0],
                                K.columns().begin() + K.row_start()[1]);
    for (const int j : cols)
      K.set(0, j, er.x * K.el(0, j) + er.y * K.el(1, j));
    for (const int i : cols)
      K.set(i, 0, er.x * K.el(i, 0) + er.y * K.el(i, 1));
    for (const int d : {1, 2})
      for (const int i : cols)
        {
          K.set(d, i, i == d ? 1.0 : 0.0);
          K.set(i, d, i == d ? 1.0 : 0.0);
        }
  }

  void RodModel::Impl::expand_trailing_end(dealii::Vector<double> &dx) const
  {
    if (!capstan || !cap.velocity || !cap.roller)
      return;
    const Vec2 er{-std::sin(u[2]), std::cos(u[2])}; // the section angle is prescribed over the step
    const double dr = dx[0];
    dx[0] = dr * er.x;
    dx[1] = dr * er.y;
    dx[2] = 0.0;
  }

  void RodModel::Impl::predict_capstan(const double step, StepState &x) const
  {
    x.u1 = u;
    if (!cap.velocity)
      return;
    const auto &cs = scene.capstan;
    const double t1 = t + step;
    const double dpsi = (cs.pushed(t1) - cs.pushed(t)) / cap.Rc;
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        const double px = u[3 * k], py = u[3 * k + 1];
        x.u1[3 * k] = std::cos(dpsi) * px + std::sin(dpsi) * py;
        x.u1[3 * k + 1] = -std::sin(dpsi) * px + std::cos(dpsi) * py;
        x.u1[3 * k + 2] -= dpsi;
      }
    // The trailing end exactly where the push puts it (radius as it was).
    const double angle = cap.a0 - cs.pushed(t1) / cap.Rc;
    const double r = cap.roller ? std::hypot(u[0], u[1]) : cap.Rc;
    x.u1[0] = r * std::cos(angle);
    x.u1[1] = r * std::sin(angle);
    x.u1[2] = angle - 0.5 * M_PI;
  }

  core::CapstanState RodModel::Impl::capstan_state() const
  {
    core::CapstanState c;
    c.wrap_angle = a_right / cap.Rc;
    c.pushed = cap.velocity ? scene.capstan.pushed(t) : 0.0;
    c.push_force = latest.push_force;
    const unsigned int lead = n_nodes - 1;
    c.lead_slide = cap.Rc * (cap.lead_angle0 - std::atan2(u[3 * lead + 1], u[3 * lead]));
    c.max_penetration = latest.max_overlap / diameter;
    const unsigned int nq = stiffness_shape.n_q;
    const dealii::QGauss<1> gauss(nq);
    const auto &states = latest.state.empty() ? qp : latest.state;
    for (unsigned int cell = 0; cell < n_cells; ++cell)
      for (unsigned int q = 0; q < nq; ++q)
        {
          const double Sq = (cell + gauss.point(q)[0]) * h;
          c.profile.push_back({{(a_right - Sq) / cap.Rc, -section.EA * states[cell * nq + q].axial_strain}});
        }
    c.trailing_compression = c.profile.empty() ? 0.0 : c.profile.front()[1];
    return c;
  }
} // namespace wirefem::fem
