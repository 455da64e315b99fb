// The rod FEM's start: the wire placed across the cavity and in its
// channels, its section angles (Kirchhoff), its initial acceleration and
// stored energy.
#include "rod_model_impl.h"

namespace wirefem::fem
{
  void RodModel::Impl::place_injected_wire(const scene::RodScene &s)
  {
    const double L0 = channels.initial_length();
    if (channels.is_tangential())
      {
        // The S (as the discrete model's: injection::Channels::initial_s).
        // The wire in a channel lies on its axis.
        for (int k = first_free; k < last_free; ++k)
          {
            const double xi = node_S[k] - a_left;
            Vec2 pos;
            double angle = channels.wire_angle();
            if (xi <= 0.0 || xi >= L0)
              pos = xi <= 0.0 ? channels.position(Side::left, xi, 0.0)
                              : channels.position(Side::right, L0 - xi, 0.0);
            else
              {
                const auto p = channels.initial_s(xi);
                pos = p.position;
                angle = p.angle;
              }
            u[3 * k] = pos.x;
            u[3 * k + 1] = pos.y;
            u[3 * k + 2] = angle;
          }
      }
    else if (wall_settings.shaped)
      place_on_initial_curve(s);
    else
      {
        const injection::InitialShape shape(s.injection.seed, s.injection.perturbation, 2.0 * radius,
                                            s.injection.mirror_asymmetry);
        for (int k = first_free; k < last_free; ++k)
          {
            const double xi = node_S[k] - a_left;
            const bool across = xi > 0.0 && xi < 2.0 * radius; // else in a channel, on its axis
            u[3 * k] = xi - radius;
            u[3 * k + 1] = across ? shape.offset(xi) : 0.0;
            u[3 * k + 2] = across ? std::atan(shape.slope(xi)) : 0.0;
          }
      }
  }

  void RodModel::Impl::place_on_initial_curve(const scene::RodScene &s)
  {
    // The discrete model's start: the curve between the inlets with the
    // seeded perturbation across it; the section angle is the direction of
    // the perturbed curve, continuous from the left channel's on.
    // One channel: the stub to the free end, which the last node reaches.
    const auto &wall = *wall_settings.shaped;
    const auto curve = injection::initial_curve(wall, h);
    const double L0 = channels.initial_length();
    const auto &in = s.injection;
    const auto shape =
        injection::initial_shape(in.seed, in.perturbation, in.mirror_asymmetry, curve, wall.mouths.size());
    const auto at = [&](const double xi) { return curve.perturbed(xi, shape); };
    const bool free_end = !channels.pushes(Side::right);
    double angle = channels.wire_angle(Side::left);
    for (int k = first_free; k < last_free; ++k)
      {
        const double xi = node_S[k] - a_left;
        Vec2 pos;
        if (xi <= 0.0 || (xi >= L0 && !free_end))
          {
            pos = xi <= 0.0 ? channels.position(Side::left, xi, 0.0)
                            : channels.position(Side::right, L0 - xi, 0.0);
            angle = channels.wire_angle(xi <= 0.0 ? Side::left : Side::right);
          }
        else
          {
            pos = at(xi);
            const double e = 1e-6 * L0;
            const Vec2 t = at(std::min(xi + e, L0)) - at(std::max(xi - e, 0.0));
            const double direction = std::atan2(t.y, t.x);
            angle += std::remainder(direction - angle, 2.0 * M_PI);
          }
        u[3 * k] = pos.x;
        u[3 * k + 1] = pos.y;
        u[3 * k + 2] = angle;
      }
  }

  void RodModel::Impl::set_initial_state(const scene::RodScene &s)
  {
    // Initial state: straight in the channels, the seeded shape across the
    // cavity, at rest.
    const unsigned int n_dofs = dof_handler.n_dofs();
    u.reinit(n_dofs);
    v.reinit(n_dofs);
    a.reinit(n_dofs);
    f_old.reinit(n_dofs);
    dissipative_old.reinit(n_dofs);
    friction_old.reinit(n_dofs);
    qp.assign(n_cells * stiffness_shape.n_q, PointState{});
    free_range(0.0, first_free, last_free);
    wall_time = 0.0;
    prescribe(0.0, u, nullptr, nullptr, first_free, last_free);
    if (clamped)
      for (int k = first_free; k < last_free; ++k)
        u[3 * k] = node_S[k]; // straight along +x
    else if (capstan)
      set_capstan_state();
    else
      place_injected_wire(s);
    if (s.fem.formulation == scene::Formulation::kirchhoff && !clamped && !capstan)
      relax_section_angles();
    // The initial acceleration, and the stored energy of the perturbed
    // wire. Where its curvature exceeds the yield curvature the wire starts
    // plastically pre-bent (the return mapping from a virgin state gives the
    // plastic curvature), so that it starts in an admissible state and the
    // initial energy is what is elastically stored.
    Evaluation e;
    dealii::Vector<double> zero(n_dofs);
    if (inertia && !explicit_mode)
      {
        // M a0 = -f(u0) on the free dofs.
        evaluate({&u, &zero, &zero, 0.0, 0.0, first_free, last_free, true, 1.0, 0.0, 0.0}, e);
        dealii::Vector<double> rhs(3 * (last_free - first_free)), x(rhs.size());
        for (unsigned int i = 0; i < rhs.size(); ++i)
          rhs[i] = -e.force[3 * first_free + i];
        if (!solve_linear(rhs, x))
          throw std::runtime_error("the mass matrix of the initial wire is singular");
        for (unsigned int i = 0; i < x.size(); ++i)
          a[3 * first_free + i] = x[i];
        f_old = e.force;
      }
    else
      evaluate({&u, &zero, &zero, 0.0, 0.0, first_free, last_free, false, 0.0, 1.0, 1.0}, e);
    // The strains of the initial shape are the reference of the first rates.
    qp = e.state;
    if (quasi_static_injection)
      {
        // Without inertia the start's perturbation must persist, or the
        // first steps straighten the wire (its bending energy falls to
        // round-off) and Newton follows the straight, compressed branch
        // through the bifurcation. The start shape is made stress-free: its
        // curvature is taken as the plastic (natural) curvature.
        for (auto &q : qp)
          q.plastic.plastic_strain = q.curvature;
        evaluate({&u, &zero, &zero, 0.0, 0.0, first_free, last_free, false, 0.0, 1.0, 1.0}, e);
        qp = e.state;
      }
    ledger.initial = e.axial + e.shear + e.bending;
    dissipative_old = e.dissipative;
    friction_old = e.friction;
  }

  void RodModel::Impl::relax_section_angles()
  {
    // The section angles placed from the curve's tangent leave each element
    // a shear strain of order h^2 times the curvature's rate, which the
    // Kirchhoff penalty (GA = FEM/Kirchhoff penalty * EA) makes a large
    // spurious energy: 574 against an injection work of 39 on the
    // continuum case at h = d, released in the first steps and lost to the
    // integrator's damping (an energy balance error of 0.83). With the
    // positions held, Newton on the angles alone minimises the elastic
    // energy instead.
    const dealii::Vector<double> zero(u.size());
    const AssemblyRequest rq{&u, &zero, &zero, 0.0, 0.0, first_free, last_free, true, 0.0, 1.0, 1.0};
    const int lo = 3 * first_free, nw = 3 * (last_free - first_free);
    dealii::Vector<double> rhs(nw), dx(nw);
    Evaluation e;
    for (unsigned int it = 0; it < scene.fem.maximum_iterations; ++it)
      {
        evaluate(rq, e);
        double r = 0.0;
        for (int i = 2; i < nw; i += 3)
          r = std::max(r, std::abs(e.residual[lo + i]));
        if (r <= newton_tolerance)
          return;
        // Positions held: their rows and columns become the identity's.
        const auto &starts = K.row_start();
        const auto &columns = K.columns();
        for (int i = 0; i < nw; ++i)
          {
            for (int q = starts[i]; q < starts[i + 1]; ++q)
              if (i % 3 != 2 || columns[q] % 3 != 2)
                K.set(i, columns[q], i == columns[q] ? 1.0 : 0.0);
            rhs[i] = i % 3 == 2 ? -e.residual[lo + i] : 0.0;
          }
        if (!solve_linear(rhs, dx))
          throw std::runtime_error("the section angles of the initial wire cannot be relaxed");
        for (int i = 2; i < nw; i += 3)
          u[lo + i] += dx[i];
      }
  }
} // namespace wirefem::fem
