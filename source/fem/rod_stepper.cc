#include "rod_model_impl.h"

#include <limits>

namespace wirefem::fem
{
  void RodModel::Impl::explicit_step(const double step)
  {
    const unsigned int n = u.size();
    int first, last;
    free_range(t + step, first, last);
    {
      core::SectionTimer::Scope ts(timer, "contact search");
      std::vector<Vec2> x(n_nodes);
      for (unsigned int k = 0; k < n_nodes; ++k)
        x[k] = position(u, k);
      broad.update(x, first_free - 1, past(last_free));
    }
    // Forces at t_n with the velocities v_n (dashpot rates over the last step).
    Evaluation e;
    const dealii::Vector<double> zero(n);
    wall_time = t;
    evaluate({&u, &zero, &v, step, 0.0, first_free, last_free, false, 0.0, 1.0, 1.0}, e);
    const std::vector<double> mass = lumped_mass(first_free, last_free);
    dealii::Vector<double> u1(u), v1(v), a1(n);
    // The wire outside the inlets at t_n follows the channels to t_{n+1}.
    prescribe(t + step, u1, &v1, &a1, first_free, last_free);
    for (int i = 3 * first_free; i < 3 * last_free; ++i)
      {
        a1[i] = -(e.force[i] + e.dissipative[i]) / mass[i];
        v1[i] = v[i] + step * a1[i];
        u1[i] = u[i] + step * v1[i];
      }
    // Reactions at the prescribed dofs include their share of inertia.
    for (unsigned int i = 0; i < n; ++i)
      if (static_cast<int>(i) < 3 * first_free || static_cast<int>(i) >= 3 * last_free)
        e.residual[i] += mass[i] * a1[i];
    history.assign(1, 0.0);
    // The next step: short enough for the stiffest regularised friction,
    // whose slope in the slip rate (friction_damping) damps the relative
    // slip of two of the lightest nodes at a rate of 2 damping / mass.
    // Explicit in the rate, a step of 2 / rate is unstable; at 1 / rate
    // the friction brings the slip to rest and no further.
    double lightest = std::numeric_limits<double>::infinity();
    for (int i = 3 * first_free; i < 3 * last_free; ++i)
      if (i % 3 != 2)
        lightest = std::min(lightest, mass[i]);
    const double friction_step = lightest / (2.0 * e.friction_damping);
    commit(step, first, last, u1, v1, a1, e, book(first, last, u1, v1, e, first_free, last_free));
    dt = std::min(dt_max, friction_step);
  }

  std::vector<double> RodModel::Impl::lumped_mass(const int first, const int last) const
  {
    std::vector<double> mass(u.size(), 0.0);
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        for (unsigned int i = 0; i < n_local; ++i)
          mass[3 * cell_node[c][i / 3] + i % 3] += lumped_element[i];
    return mass;
  }

  void RodModel::Impl::predict(const double step, const int first, const int last, StepState &x) const
  {
    // Constant acceleration (or velocity, FEM/Predictor) for the free dofs,
    // the channel motion for the prescribed ones.
    const unsigned int n = u.size();
    x.u1 = u;
    x.v1.reinit(n);
    x.a1.reinit(n);
    x.v0.reinit(n);
    x.a_blend.reinit(n);
    x.u_hat.reinit(n);
    const double a_weight = velocity_predictor ? 0.0 : 0.5 * step * step;
    for (unsigned int i = 0; i < n; ++i)
      x.u1[i] = u[i] + step * v[i] + a_weight * a[i];
    if (capstan)
      predict_capstan(step, x);
    prescribe(t + step, x.u1, nullptr, nullptr, first, last);
    x.step = step;
    x.c_vel = inertia ? gamma / (beta * step) : 1.0 / step;
    x.beta = beta;
    x.alpha_m = alpha_m;
    x.inertia = inertia;
    x.a_n = &a;
    for (unsigned int i = 0; i < n; ++i)
      {
        x.u_hat[i] = u[i] + step * v[i] + step * step * (0.5 - beta) * a[i];
        x.v0[i] = inertia ? v[i] + step * (1.0 - gamma) * a[i] - x.c_vel * x.u_hat[i] : -u[i] / step;
      }
    x.update();
  }

  AssemblyRequest RodModel::Impl::start_step(const double step, StepState &x)
  {
    wall_time = t + step;
    int first, last;
    free_range(wall_time, first, last);
    predict(step, first, last, x);
    if (!clamped && !capstan) // the other loadings have no self contact
      update_contact_candidates(first, last);
    const double c_mass = inertia ? (1.0 - alpha_m) / (beta * step * step) : 0.0;
    const double c_force = 1.0 - alpha_f;
    AssemblyRequest rq{&x.u1, &x.a_blend, &x.v0, step, x.c_vel, first, last, true, c_mass, c_force, c_force};
    // Quasi-static injection: friction measures the slip of a step over
    // the longest step, not its rate, so that its regularisation does not
    // sharpen into a jump as steps are cut (Newton then stalls at the first
    // self contact).
    if (quasi_static_step())
      {
        // FEM/Quasi-static creep: the law's slip scale is that fraction of
        // the longest step's injection (dt_max times the speed); 0: v_th
        // times dt_max, the dynamic law's, whose creep grows as the speed falls.
        const double creep = scene.fem.quasi_static_creep;
        const double slip = creep * dt_max * scene.injection.speed;
        rq.friction_rate = step / (creep > 0 ? slip / regularised_threshold(self_settings) : dt_max);
      }
    return rq;
  }

  void RodModel::Impl::newton_rhs(const Evaluation &ev, const AssemblyRequest &rq,
                                  dealii::Vector<double> &rhs) const
  {
    const int lo = 3 * rq.first;
    for (unsigned int i = 0; i < rhs.size(); ++i)
      rhs[i] = -(ev.residual[lo + i] + alpha_f * f_old[lo + i]);
  }

  double RodModel::Impl::free_residual_norm(const Evaluation &ev, const int first, const int last) const
  {
    // The max norm over the free dofs of the (generalized-alpha blended)
    // residual; infinite when any entry is not finite.
    double r = 0;
    for (int i = 3 * first; i < 3 * last; ++i)
      {
        const double ri = ev.residual[i] + alpha_f * f_old[i];
        if (!std::isfinite(ri))
          return INFINITY;
        r = std::max(r, std::abs(ri));
      }
    return r;
  }

  void RodModel::Impl::update_contact_candidates(const int first, const int last)
  {
    core::SectionTimer::Scope ts(timer, "contact search");
    broad.update(node_positions(u), first - 1, past(last));
  }

  std::vector<Vec2> RodModel::Impl::node_positions(const dealii::Vector<double> &x) const
  {
    std::vector<Vec2> xs(n_nodes);
    for (unsigned int k = 0; k < n_nodes; ++k)
      xs[k] = position(x, k);
    return xs;
  }

  void RodModel::Impl::log_jump(const double step, const int first, const int last,
                                const dealii::Vector<double> &u1) const
  {
    double jump = 0.0;
    int at = 0;
    for (int k = first; k < last; ++k)
      if (const double dk = norm(position(u1, k) - position(u, k)); dk > jump)
        jump = dk, at = k;
    if (jump > 0.25 * diameter)
      std::cerr << fmt::format("t = {:.5g}: quasi-static step moved node {} by {:.3g} d\n", t + step, at,
                               jump / diameter);
  }

  bool RodModel::Impl::saw_every_contact(const dealii::Vector<double> &x, const int first, const int last)
  {
    if (clamped || capstan) // no self contact
      return true;
    core::SectionTimer::Scope ts(timer, "contact search");
    const std::vector<Vec2> xs = node_positions(x);
    if (broad.covers(xs, first - 1, past(last)))
      return true;
    const std::vector<contact::SegmentPair> seen = broad.candidates();
    broad.update(xs, first - 1, past(last));
    for (const auto &pr : broad.candidates())
      if (closer_than(x, pr, diameter) && !std::binary_search(seen.begin(), seen.end(), pr))
        return false;
    return true;
  }

  void RodModel::Impl::move_along(const AssemblyRequest &rq, StepState &x,
                                  const dealii::Vector<double> &u_start, const dealii::Vector<double> &dx,
                                  const double lambda) const
  {
    const int lo = 3 * rq.first, nw = 3 * (rq.last - rq.first);
    for (int i = 0; i < nw; ++i)
      x.u1[lo + i] = u_start[lo + i] + lambda * dx[i];
    x.update();
  }

  void RodModel::Impl::backtrack(const AssemblyRequest &rq, StepState &x,
                                 const dealii::Vector<double> &u_start, const dealii::Vector<double> &dx,
                                 const double res, Evaluation &trial)
  {
    // Armijo on the max norm, halving the update up to five times; the
    // residual only (the caller assembles the tangent where it stops).
    double lambda = 1.0;
    for (int ls = 0; ls < 5; ++ls)
      {
        lambda *= 0.5;
        move_along(rq, x, u_start, dx, lambda);
        evaluate(rq.without_tangent(), trial);
        if (free_residual_norm(trial, rq.first, rq.last) < (1.0 - 1e-4 * lambda) * res)
          break;
      }
  }

  double RodModel::Impl::newton_update(const AssemblyRequest &rq, StepState &x,
                                       const dealii::Vector<double> &dx, const double res, Evaluation &e,
                                       Evaluation &trial)
  {
    // Full Newton update, with the tangent there; if the residual does not
    // drop, backtrack and re-linearise (unless line_search is off: then
    // always the full update). Where the update likely converges, the
    // residual alone first: the step ends there and needs no tangent.
    const dealii::Vector<double> u_start(x.u1);
    move_along(rq, x, u_start, dx, 1.0);
    const bool no_tangent = likely_converges(res);
    tangents_skipped += no_tangent ? 1 : 0;
    evaluate(no_tangent ? rq.without_tangent() : rq, trial);
    double r_new = free_residual_norm(trial, rq.first, rq.last);
    if (no_tangent && r_new > newton_tolerance)
      {
        ++tangents_missed;
        evaluate(rq, trial);
        r_new = free_residual_norm(trial, rq.first, rq.last);
      }
    if (!line_search || r_new < (1.0 - 1e-4) * res || (no_tangent && r_new <= newton_tolerance))
      {
        std::swap(e, trial);
        return r_new;
      }
    backtrack(rq, x, u_start, dx, res, trial);
    evaluate(rq, e);
    return free_residual_norm(e, rq.first, rq.last);
  }

  bool RodModel::Impl::likely_converges(const double res) const
  {
    // The contraction of the last update, repeated: quadratic convergence
    // does at least as well.
    if (clamped || capstan || history.size() < 2)
      return false;
    const double before = history[history.size() - 2];
    return before > 0.0 && res * (res / before) < newton_tolerance;
  }

  double RodModel::Impl::modified_update(const AssemblyRequest &rq, StepState &x,
                                         const dealii::Vector<double> &dx, const double res, bool &fresh,
                                         Evaluation &e, Evaluation &trial)
  {
    // The update, and the residual alone there: converged, or contracted
    // enough that the next solve may reuse the factors (no tangent needed).
    const dealii::Vector<double> u_start(x.u1);
    move_along(rq, x, u_start, dx, 1.0);
    evaluate(rq.without_tangent(), trial);
    const double r_new = free_residual_norm(trial, rq.first, rq.last);
    const bool was_fresh = fresh;
    fresh = true;
    if (r_new <= newton_tolerance || r_new <= newton_contraction * res)
      {
        std::swap(e, trial);
        fresh = false;
        return r_new;
      }
    if (r_new < (1.0 - 1e-4) * res || (was_fresh && !line_search))
      {
        // Progress, but slow: a tangent at the state reached.
        evaluate(rq, e);
        return r_new;
      }
    if (was_fresh)
      backtrack(rq, x, u_start, dx, res, trial);
    else
      {
        // The kept factors no longer point downhill: a tangent where the
        // update started.
        x.u1 = u_start;
        x.update();
      }
    evaluate(rq, e);
    return free_residual_norm(e, rq.first, rq.last);
  }

  RodModel::Impl::StepOutcome RodModel::Impl::solve_step(const double step, const bool kept)
  {
    const unsigned int n = u.size();
    StepState x;
    const AssemblyRequest rq = start_step(step, x);
    const int first = rq.first, last = rq.last;
    auto &u1 = x.u1;
    const double tol = newton_tolerance;
    const int nw = 3 * (last - first);
    auto residual_norm = [&](const Evaluation &ev) { return free_residual_norm(ev, first, last); };

    history.clear();
    step_tangents = 0;
    bool fresh = true; // K is the tangent at x.u1, to be factorised
    Evaluation e, trial;
    dealii::Vector<double> rhs(nw), dx(nw);
    evaluate(rq, e);
    if (predictor_probe)
      {
        // A test looks at the first assembly of the step (it may move x.u1
        // and reassemble; it leaves them as they were).
        predictor_probe(rq, x);
        evaluate(rq, e);
      }
    double res = residual_norm(e);
    history.push_back(res);
    // Up to Maximum iterations solves; the residual after the last is
    // checked too.
    for (unsigned int it = 0; it <= scene.fem.maximum_iterations; ++it)
      {
        if (res <= tol)
          {
            // A contact Newton did not see: the step is cut like one
            // that failed.
            if (!saw_every_contact(u1, first, last))
              return StepOutcome::missed_contact;
            // An impact crossed in one step: shorter steps, down to 1/16
            // of the step cap.
            if (overlap_growth > 0 && e.max_overlap > last_report.max_penetration + overlap_growth &&
                0.5 * step >= dt_max / 16)
              return StepOutcome::overlap_grew;
            for (unsigned int i = 0; i < n; ++i)
              e.residual[i] += alpha_f * f_old[i];
            const Booking b = book(first, last, u1, x.v1, e, first, last);
            // A local or energy error above four times its target: a
            // shorter step, down to 1/64 of the step cap. (Within that, the
            // next step is set from the estimates: a step made again costs
            // a whole Newton iteration.)
            if (estimate_errors(x, first, last, b.ledger) > 4.0 && step > dt_max / 64)
              return StepOutcome::error_too_large;
            commit(step, first, last, u1, x.v1, x.a1, e, b);
            return StepOutcome::converged;
          }
        if (!std::isfinite(res) || it == scene.fem.maximum_iterations)
          return StepOutcome::not_converged;
        newton_rhs(e, rq, rhs);
        {
          core::SectionTimer::Scope ts(timer, "linear solve");
          // Kept factors: an inexact Newton step, the linear residual a
          // small fraction of the nonlinear one, or of the tolerance.
          const double linear_tolerance =
              kept ? std::max(scene.fem.linear_tolerance * rhs.l2_norm(), scene.fem.linear_floor * tol) : 0.0;
          step_tangents += fresh ? 1 : 0;
          if (!(fresh ? solve_linear(rhs, dx, linear_tolerance) : solve_factorised(rhs, dx)))
            return StepOutcome::not_converged;
          ++newton_iterations;
        }
        expand_trailing_end(dx);
        res = modified_newton ? modified_update(rq, x, dx, res, fresh, e, trial)
                              : newton_update(rq, x, dx, res, e, trial);
        history.push_back(res);
      }
    return StepOutcome::not_converged;
  }

  double RodModel::Impl::estimate_errors(const StepState &x, const int first, const int last,
                                         const core::EnergyLedger &after)
  {
    const bool control = step_error > 0 && x.inertia;
    error_estimate = control ? local_error(x, first, last) : 0.0;
    energy_estimate = control && step_energy_error > 0 ? energy_error(after, x.step) : 0.0;
    error_ratio = control ? std::max(error_estimate / step_error,
                                     step_energy_error > 0 ? energy_estimate / step_energy_error : 0.0)
                          : 0.0;
    // FEM/Quasi-static energy error: a quasi-static injection step whose
    // own imbalance (the error of its trapezoidal booking) is over four
    // times that fraction of its share of the energy put in is made again,
    // shorter. Below that its step is left as it was (the ratio 0).
    const double qs_target = scene.fem.quasi_static_energy_error;
    // (Not the start shape's relaxation, which ends at t = 0.)
    if (quasi_static_step() && qs_target > 0 && t + x.step > 0)
      {
        energy_estimate = energy_error(after, x.step, false);
        const double ratio = energy_estimate / qs_target;
        error_ratio = ratio > 4.0 ? ratio : 0.0;
      }
    return error_ratio;
  }

  double RodModel::Impl::local_error(const StepState &x, const int first, const int last) const
  {
    // The update's displacement minus a third-order one, to leading order
    // h^2 (beta - 1/6) (a_{n+1} - a_n); a section angle counts as the arc
    // it turns at the wire's surface.
    double jump = 0;
    for (int i = 3 * first; i < 3 * last; ++i)
      jump = std::max(jump, std::abs(x.a1[i] - a[i]) * (i % 3 == 2 ? 0.5 * diameter : 1.0));
    return std::abs(x.beta - 1.0 / 6.0) * x.step * x.step * jump;
  }

  std::string RodModel::Impl::residual_history() const
  {
    std::string h;
    for (const double r : history)
      h += fmt::format(" {:.2e}", r);
    return h;
  }

  void RodModel::Impl::enter_dynamics()
  {
    const double at = injected_at(t);
    const bool again = last_snap_at >= 0.0 && at - last_snap_at < qs_again * diameter;
    last_snap_at = at;
    // From the last equilibrium, at rest; the channels held, or (a snap
    // where the last one was) pushing first.
    use_integrator(true);
    v = 0.0;
    a = 0.0;
    if (again)
      {
        push_to = at + qs_push * diameter;
        ++pushes;
      }
    else
      pause_from = t;
    dt = dt_max;
    calm_steps = 0;
    ++snaps;
    if (std::getenv("WIREFEM_NEWTON_LOG"))
      std::cerr << fmt::format("t = {:.5g}: a snap; generalized-alpha, {}\n", t,
                               again ? "pushing first" : "the injection paused");
  }

  void RodModel::Impl::after_dynamic_step()
  {
    ++dynamic_steps;
    if (push_to && injected_at(t) >= *push_to)
      {
        push_to.reset();
        pause_from = t;
      }
    calm_steps = pause_from && ledger.kinetic <= qs_calm * ledger.stored() ? calm_steps + 1 : 0;
    if (calm_steps >= qs_calm_steps)
      leave_dynamics();
  }

  void RodModel::Impl::leave_dynamics()
  {
    // What kinetic energy is left is taken out with the velocities; the
    // ledger books it as damping.
    ledger.damping += ledger.kinetic;
    ledger.kinetic = 0.0;
    use_integrator(false);
    v = 0.0;
    a = 0.0;
    paused_total += t - *pause_from;
    pause_from.reset();
    dt = dt_max / 64.0;
    if (std::getenv("WIREFEM_NEWTON_LOG"))
      std::cerr << fmt::format("t = {:.5g}: back to quasi-static after {} dynamic steps in all\n", t,
                               dynamic_steps);
  }

  void RodModel::Impl::use_integrator(const bool dynamic)
  {
    inertia = dynamic;
    use_alpha(dynamic);
    dt_max = dynamic ? dynamic_dt_max : qs_dt_max;
  }

  void RodModel::Impl::save_quasi_static(std::ostream &out) const
  {
    core::write_raw(out, static_cast<int>(pause_from ? 1 : push_to ? 2 : 0));
    core::write_raw(out, pause_from.value_or(push_to.value_or(-1.0)));
    core::write_raw(out, paused_total);
    core::write_raw(out, calm_steps);
    core::write_raw(out, snaps);
    core::write_raw(out, dynamic_steps);
    core::write_raw(out, pushes);
    core::write_raw(out, last_snap_at);
  }

  void RodModel::Impl::load_quasi_static(std::istream &in)
  {
    // Phase 0: quasi-static; 1: paused since `at`; 2: pushing to `at`.
    const int phase = core::read_raw<int>(in);
    const double at = core::read_raw<double>(in), total = core::read_raw<double>(in);
    if (phase < 0 || phase > 2 || (phase && !quasi_static_injection) || !std::isfinite(at) ||
        !std::isfinite(total) || total < 0.0 || (phase && at < 0.0))
      throw std::runtime_error("checkpoint holds an impossible quasi-static state");
    if (phase)
      use_integrator(true);
    if (phase == 1)
      pause_from = at;
    if (phase == 2)
      push_to = at;
    paused_total = total;
    calm_steps = core::read_raw<unsigned long>(in);
    snaps = core::read_raw<unsigned long>(in);
    dynamic_steps = core::read_raw<unsigned long>(in);
    pushes = core::read_raw<unsigned long>(in);
    last_snap_at = core::read_raw<double>(in);
    if (!std::isfinite(last_snap_at))
      throw std::runtime_error("checkpoint holds an impossible quasi-static state");
  }
} // namespace wirefem::fem
