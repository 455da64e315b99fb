#include "rod_model_impl.h"

// The energy ledger of a step: what each step books, and the commit.
namespace wirefem::fem
{
  double RodModel::Impl::cell_kinetic(const unsigned int c, const dealii::Vector<double> &vel) const
  {
    const unsigned int nd = n_local;
    double ek = 0;
    for (unsigned int i = 0; i < nd; ++i)
      {
        const double vi = vel[3 * cell_node[c][i / 3] + i % 3];
        if (explicit_mode)
          ek += 0.5 * lumped_element[i] * vi * vi;
        else
          for (unsigned int j = 0; j < nd; ++j)
            ek += 0.5 * vi * element_mass[i * nd + j] * vel[3 * cell_node[c][j / 3] + j % 3];
      }
    return ek;
  }

  double RodModel::Impl::kinetic_energy(const dealii::Vector<double> &vel, const int first,
                                        const int last) const
  {
    if (!inertia)
      return 0.0;
    double ek = 0;
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        ek += cell_kinetic(c, vel);
    return ek;
  }

  RodModel::Impl::Booking RodModel::Impl::book(const int first, const int last,
                                               const dealii::Vector<double> &u1,
                                               const dealii::Vector<double> &v1, const Evaluation &e,
                                               const int work_first, const int work_last) const
  {
    const unsigned int n = u.size();
    Booking b{ledger};
    auto &l = b.ledger;
    // Wire that entered the system this step brings its kinetic energy.
    if (first < first_free || last > last_free)
      {
        double before = 0;
        for (unsigned int c = 0; c < n_cells; ++c)
          if (inertia && cell_active(c, first, last) && !cell_active(c, first_free, last_free))
            before += cell_kinetic(c, v);
        l.injection_work += before;
      }
    // Quasi-static steps book the work of the forces by the trapezoidal
    // rule, with the forces of the equilibria at both ends of the step
    // (both ends are equilibria, so the balance closes to second order in
    // the step). The end forces alone, as the dynamic steps book them,
    // leave a first-order error that strong wall friction makes large
    // (9.6e-2 at mu_st 5 on the f = 10 classic scene, against 7.4e-4), and
    // miss the work of a node's reaction as the node leaves its channel.
    const bool trapezoid = quasi_static_step();
    channel_work(u1, e, work_first, work_last, trapezoid, b.work);
    for (const double w : b.work)
      l.injection_work += w;
    // Friction and dashpots: the work of their nodal forces (at the end of
    // the step) against the motion of the nodes. For the dashpots this is
    // N_v (dN/du) du rather than N_v d(eps): the two differ at second order
    // in the step because the strains are nonlinear in u, and only the
    // first is the energy the time step actually removed (the difference
    // made a first-order drift of the balance in dynamic scenes).
    const double w1 = trapezoid ? 0.5 : 1.0, w0 = 1.0 - w1;
    double friction = 0, viscous = 0;
    for (unsigned int i = 0; i < n; ++i)
      {
        const double du_i = u1[i] - u[i];
        const double fr = w1 * e.friction[i] + w0 * friction_old[i];
        friction += fr * du_i;
        viscous += (w1 * e.dissipative[i] + w0 * dissipative_old[i] - fr) * du_i;
      }
    // Under the spring law the friction forces also load the wall springs:
    // what they hold is stored, not dissipated (as in the discrete model).
    l.friction += friction - (e.friction_stored - l.friction_stored);
    l.friction_stored = e.friction_stored;
    l.plastic += e.plastic;
    l.damping += viscous;
    l.stretching = e.axial;
    l.shear = e.shear;
    l.bending = e.bending;
    l.contact = e.contact;
    l.kinetic = kinetic_energy(v1, first, last);
    return b;
  }

  double RodModel::Impl::energy_error(const core::EnergyLedger &after, const double step,
                                      const bool with_last) const
  {
    // The imbalance over its share of the energy put in (that energy times
    // the length over the time). Generalized-alpha takes this step and the
    // one before: with rho_inf < 1 it leaves a decaying part in the
    // accelerations that alternates from step to step (it is excited by
    // every contact), and with it the imbalance of a single step, which
    // then does not fall with the step; over two steps it mostly cancels.
    if (after.in() <= 0.0)
      return 0.0;
    const double own = after.imbalance() - ledger.imbalance();
    const double imbalance = with_last ? own + last_imbalance : own;
    return std::abs(imbalance) / (after.in() * (with_last ? step + last_step : step) / (t + step));
  }

  void RodModel::Impl::commit(const double step, const int first, const int last,
                              const dealii::Vector<double> &u1, const dealii::Vector<double> &v1,
                              const dealii::Vector<double> &a1, Evaluation &e, const Booking &b)
  {
    if (quasi_static_step() && std::getenv("WIREFEM_NEWTON_LOG"))
      log_jump(step, first, last, u1);
    const double du = injected_at(t + step) - injected_at(t);
    for (int side = 0; side < 2; ++side)
      window[side].add(du, b.work[side]);
    last_imbalance = b.ledger.imbalance() - ledger.imbalance();
    last_step = step;
    ledger = b.ledger;
    last_report = {e.max_overlap, static_cast<int>(e.pairs.size()), e.n_wall};
    if (wall_spring && !e.wall_history.empty())
      {
        // The springs continue from where e was taken (explicit: u_n).
        wall_springs = e.wall_history;
        note_spring_positions(explicit_mode ? u : u1);
      }
    self_springs.commit(std::move(e.self_history)); // (none but under FEM/Self friction law = spring)
    u = u1;
    v = v1;
    a = a1;
    f_old = e.force;
    dissipative_old = e.dissipative;
    friction_old = e.friction;
    qp = e.state;
    t += step;
    ++steps;
    first_free = first;
    last_free = last;
    latest = std::move(e);
  }

  void RodModel::Impl::channel_work(const dealii::Vector<double> &u1, const Evaluation &e,
                                    const int work_first, const int work_last, const bool trapezoid,
                                    double (&work)[2]) const
  {
    // The reactions at the prescribed dofs of the active cells: at the end
    // of the step, or (trapezoid) the mean of the step's two ends, where a
    // node that left its channel this step has no reaction at the end.
    std::vector<char> counted(n_nodes, 0);
    auto held = [](const int k, const int lo, const int hi) { return k < lo || k >= hi; };
    const double w1 = trapezoid ? 0.5 : 1.0, w0 = 1.0 - w1;
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, work_first, work_last))
        for (const auto k : cell_node[c])
          {
            const int ki = static_cast<int>(k);
            const bool held_now = held(ki, work_first, work_last);
            const bool held_before = trapezoid && held(ki, first_free, last_free);
            if ((!held_now && !held_before) || counted[k])
              continue;
            counted[k] = 1;
            double w = 0;
            for (unsigned int cc = 0; cc < 3; ++cc)
              {
                const unsigned int i = 3 * k + cc;
                const double r = (held_now ? w1 * e.residual[i] : 0.0) +
                                 (held_before ? w0 * (f_old[i] + dissipative_old[i]) : 0.0);
                w += r * (u1[i] - u[i]);
              }
            work[2 * ki < work_first + work_last ? 0 : 1] += w;
          }
  }
} // namespace wirefem::fem
