#include "rod_model_impl.h"

namespace wirefem::fem
{
  namespace
  {
    constexpr std::uint64_t fem_magic = 0x77666d66656d3037ull; // "wfmfem07"
    // Written byte for byte into the checkpoint: no padding.
    static_assert(sizeof(core::StepReport) == sizeof(double) + 2 * sizeof(int), "StepReport has padding");

    /// FEM/Step error: the factor on the step that brings the larger ratio
    /// of an error estimate to its target to 1 (with a margin of 0.9; the
    /// local error goes as h^3).
    double error_factor(const double ratio)
    {
      return 0.9 * std::cbrt(1.0 / ratio);
    }
  } // namespace

  RodModel::RodModel(const scene::RodScene &scene)
    : impl(std::make_unique<Impl>(scene))
  {
  }

  RodModel::~RodModel() = default;

  std::string RodModel::description() const
  {
    const auto &s = impl->scene.fem;
    const std::string integrator = impl->clamped                                     ? "static load path"
                                   : s.integrator == scene::Integrator::quasi_static ? "quasi-static"
                                   : s.integrator == scene::Integrator::explicit_lumped
                                       ? "explicit (lumped mass)"
                                       : fmt::format("generalized-alpha rho = {}", s.spectral_radius);
    const std::string along =
        impl->segment_points.empty() ? "" : fmt::format(", contact at {} points a segment", s.contact_points);
    const std::string rod =
        fmt::format("{} rod, degree {}, h = {:g}, {} dofs{}, {}",
                    s.formulation == scene::Formulation::kirchhoff ? "Kirchhoff" : "Reissner", s.degree,
                    impl->h, impl->dof_handler.n_dofs(), along, integrator);
    if (impl->clamped)
      return rod;
    return fmt::format("{}, dt <= {:.4g}", rod, impl->dt_max);
  }

  void RodModel::step()
  {
    auto &m = *impl;
    if (m.explicit_mode)
      {
        m.explicit_step(m.dt);
        return;
      }
    double step = m.dt;
    // The capstan's slide ends at its time.
    if (m.capstan && m.cap.velocity)
      step = std::min(step, m.cap.t_end - m.t);
    while (true)
      {
        using Outcome = Impl::StepOutcome;
        auto attempt = [&](const bool kept) {
          try
            {
              return m.solve_step(step, kept);
            }
          catch (const dealii::ExceptionBase &)
            {
              return Outcome::not_converged;
            }
        };
        auto outcome = attempt(m.kept_factors || m.band_solver);
        if (outcome == Outcome::not_converged && (m.kept_factors || m.band_solver))
          {
            // Inexact linear solves may be what failed: the same step once
            // more with a factorisation per iteration, before it is cut.
            ++m.retried_steps;
            outcome = attempt(false);
          }
        if (outcome == Outcome::converged)
          break;
        if (outcome == Outcome::overlap_grew || outcome == Outcome::error_too_large)
          {
            // Shorter: by half for an overlap, by the estimate for an error.
            const bool overlap = outcome == Outcome::overlap_grew;
            ++(overlap ? m.overlap_cuts : m.error_cuts);
            step *= overlap ? 0.5 : std::clamp(error_factor(m.error_ratio), 0.25, 0.9);
            continue;
          }
        ++m.cuts;
        if (std::getenv("WIREFEM_NEWTON_LOG"))
          std::cerr << fmt::format("t = {:.5g}: step {:.3g} cut; {}residuals{}\n", m.t, step,
                                   outcome == Outcome::missed_contact ? "Newton missed a contact; " : "",
                                   m.residual_history());
        step *= 0.5;
        if (m.quasi_static_step() && step < m.scene.fem.minimum_time_step)
          {
            // A snap: no equilibrium near. Dynamics takes it.
            m.enter_dynamics();
            step = m.dt;
            continue;
          }
        if (step < m.scene.fem.minimum_time_step)
          throw std::runtime_error(fmt::format("Newton did not converge at t = {:.6g} even with the time "
                                               "step cut to {:.3g} (below FEM/Minimum "
                                               "time step {:.3g}); last residual {:.3g}",
                                               m.t, 2.0 * step, m.scene.fem.minimum_time_step,
                                               m.history.empty() ? NAN : m.history.back()));
      }
    if (const char *log = std::getenv("WIREFEM_NEWTON_LOG"); log && std::string(log) == "all")
      std::cerr << fmt::format("t = {:.5g}: step {:.3g} converged; residuals{}\n", m.t, step,
                               m.residual_history());
    // Grow the step again when Newton had an easy time: at most three
    // iterations, or (modified Newton) at most two tangents in five.
    const std::size_t iterations = m.history.size() - 1;
    const bool easy = iterations <= 3 || (m.modified_newton && m.step_tangents <= 2 && iterations <= 5);
    // FEM/Step error: the step the estimates ask for, by at most twice (not
    // longer after a hard Newton), down to 1/64 of the cap (part of the
    // energy estimate does not shrink with the step).
    const double grow = m.error_ratio > 0 ? std::clamp(error_factor(m.error_ratio), 0.5, 2.0) : 1.5;
    m.dt = std::min(m.dt_max, step * (easy ? grow : std::min(grow, 1.0)));
    if (grow < 1.0)
      m.dt = std::max(m.dt, std::min(step, m.dt_max / 64));
    if (m.dynamic_phase())
      m.after_dynamic_step();
  }

  double RodModel::time() const
  {
    return impl->t;
  }
  double RodModel::time_step() const
  {
    return impl->dt;
  }
  unsigned long RodModel::n_steps() const
  {
    return impl->steps;
  }
  double RodModel::injected_length() const
  {
    return impl->channels.injected_length(impl->injection_time(impl->t));
  }
  double RodModel::force_left() const
  {
    return impl->window[0].mean();
  }
  double RodModel::force_right() const
  {
    return impl->window[1].mean();
  }
  const core::EnergyLedger &RodModel::energies() const
  {
    return impl->ledger;
  }
  core::StepReport RodModel::report() const
  {
    return impl->last_report;
  }
  const std::vector<std::string> &RodModel::active_effects() const
  {
    return impl->effects;
  }
  const std::vector<double> &RodModel::newton_history() const
  {
    return impl->history;
  }
  unsigned long RodModel::n_step_cuts() const
  {
    return impl->cuts;
  }

  unsigned int RodModel::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }

  bool RodModel::finite() const
  {
    for (int i = 3 * impl->first_free; i < 3 * impl->last_free; ++i)
      if (!std::isfinite(impl->u[i]) || !std::isfinite(impl->v[i]))
        return false;
    return true;
  }

  core::WireState RodModel::wire_state() const
  {
    const auto &m = *impl;
    core::WireState w;
    w.diameter = m.diameter;
    w.cavity_radius = m.radius;
    if (m.wall_settings.shaped)
      m.wall_settings.shaped->describe(w);
    w.time = m.t;
    w.injected_length = injected_length();
    // The inlets, and the free nodes between them.
    const double s0 = m.left_inlet_S(m.t);
    int k0, k1;
    m.inside_range(m.t, k0, k1);
    // (One channel: the last free node is the wire's free end.)
    const bool two = m.channels.pushes(Side::right);
    const int n = k1 - k0 + (two ? 2 : 1);
    w.resize(n);
    w.points[0] = m.channels.inlet(Side::left);
    if (two)
      w.points[n - 1] = m.channels.inlet(Side::right);
    w.arc_length[n - 1] = injected_length();
    const double EI = m.scene.wire.bending_stiffness;
    // Curvature and plastic curvature at a node: mean over the quadrature
    // points of the elements around it.
    std::vector<double> kappa(m.n_nodes, 0.0), kappa_p(m.n_nodes, 0.0), count(m.n_nodes, 0.0);
    const unsigned int nq = m.stiffness_shape.n_q;
    for (unsigned int c = 0; c < m.n_cells; ++c)
      if (m.cell_active(c, k0, k1))
        for (const auto k : m.cell_node[c])
          for (unsigned int q = 0; q < nq; ++q)
            {
              kappa[k] += m.qp[c * nq + q].curvature;
              kappa_p[k] += m.qp[c * nq + q].plastic.plastic_strain;
              count[k] += 1.0;
            }
    for (int k = k0; k < k1; ++k)
      {
        const int i = k - k0 + 1;
        w.points[i] = m.position(m.u, k);
        w.arc_length[i] = m.node_S[k] - s0;
        if (count[k] > 0)
          {
            w.curvature[i] = kappa[k] / count[k];
            w.plastic_curvature[i] = kappa_p[k] / count[k];
          }
        const double ke = w.curvature[i] - w.plastic_curvature[i];
        w.bending_energy[i] = 0.5 * EI * ke * ke * m.node_weight(k);
        if (!m.latest.node_contact_force.empty())
          w.contact_force[i] = m.latest.node_contact_force[k];
      }
    auto point_of = [&](int k, double s) {
      return std::clamp(static_cast<int>(std::lround(k - k0 + 1 + s)), 0, n - 1);
    };
    for (const auto &pr : m.latest.pairs)
      {
        core::SelfContact sc;
        sc.s_a = m.node_S[pr.i] + pr.s * (m.node_S[pr.i + 1] - m.node_S[pr.i]) - s0;
        sc.s_b = m.node_S[pr.j] + pr.t * (m.node_S[pr.j + 1] - m.node_S[pr.j]) - s0;
        sc.point_a = point_of(pr.i, pr.s);
        sc.point_b = point_of(pr.j, pr.t);
        sc.x_a = (1.0 - pr.s) * m.position(m.u, pr.i) + pr.s * m.position(m.u, pr.i + 1);
        sc.x_b = (1.0 - pr.t) * m.position(m.u, pr.j) + pr.t * m.position(m.u, pr.j + 1);
        sc.normal_force = pr.fn;
        w.self_contacts.push_back(sc);
      }
    return w;
  }

  namespace
  {
    void write_dealii_vector(std::ostream &out, const dealii::Vector<double> &x)
    {
      const std::vector<double> v(x.begin(), x.end());
      core::write_vector(out, v, 0, v.size());
    }
    void read_dealii_vector(std::istream &in, dealii::Vector<double> &x)
    {
      std::vector<double> v(x.size());
      if (core::peek_vector_size(in) != v.size())
        throw std::runtime_error("checkpoint does not fit this scene");
      core::read_vector(in, v);
      std::copy(v.begin(), v.end(), x.begin());
    }
  } // namespace

  core::Equilibrium RodModel::equilibrate(const double load_factor)
  {
    if (!impl->clamped)
      return core::Model::equilibrate(load_factor);
    return impl->follow_load(load_factor);
  }

  core::CapstanState RodModel::capstan_state() const
  {
    if (!impl->capstan)
      return core::Model::capstan_state();
    return impl->capstan_state();
  }

  std::vector<std::pair<std::string, double>> RodModel::statistics() const
  {
    const auto &m = *impl;
    if (m.capstan)
      {
        // The coefficient steady sliding mobilises at the push speed (mu_d
        // under the spring law).
        const double sliding = m.wall_spring ? m.wall_settings.mu_dynamic
                                             : sliding_coefficient(m.wall_settings, m.scene.capstan.speed);
        return {{"elements", m.n_cells},
                {"degree", m.p},
                {"element_length", m.h},
                {"sliding_coefficient", sliding},
                {"capstan_sliding", m.scene.capstan.end_force * std::exp(sliding * m.a_right / m.cap.Rc)},
                {"time_step", m.dt_max},
                {"newton_iterations", static_cast<double>(m.newton_iterations)},
                {"step_cuts", static_cast<double>(m.cuts)}};
      }
    if (!m.clamped)
      {
        // The injection scenes: the solver's work, independent of the
        // machine (a Newton iteration is one linear solve).
        const auto &ls = m.lu.statistics();
        return {{"newton_iterations", static_cast<double>(m.newton_iterations)},
                {"step_cuts", static_cast<double>(m.cuts)},
                {"overlap_cuts", static_cast<double>(m.overlap_cuts)},
                {"error_cuts", static_cast<double>(m.error_cuts)},
                {"factorisations", static_cast<double>(ls.factorisations + ls.refactorisations)}};
      }
    return {{"elements", m.n_cells},
            {"element_length", m.h},
            {"degree", m.p},
            {"load_increments", static_cast<double>(m.path.increments)},
            {"newton_iterations", static_cast<double>(m.newton_iterations)},
            {"lowest_eigenvalue", m.path.lowest_eigenvalue},
            {"unstable_states_left", m.path.unstable_states_left}};
  }

  void RodModel::save(std::ostream &out) const
  {
    const auto &m = *impl;
    core::write_raw(out, fem_magic);
    core::write_raw(out, static_cast<std::uint64_t>(m.u.size()));
    for (const auto *x : {&m.u, &m.v, &m.a, &m.f_old, &m.dissipative_old, &m.friction_old})
      write_dealii_vector(out, *x);
    core::write_vector(out, m.qp, 0, m.qp.size());
    core::write_raw(out, m.t);
    core::write_raw(out, m.dt);
    core::write_raw(out, m.steps);
    core::write_raw(out, m.cuts);
    core::write_raw(out, m.overlap_cuts);
    core::write_raw(out, m.error_cuts);
    core::write_raw(out, m.last_imbalance);
    core::write_raw(out, m.last_step);
    core::write_raw(out, m.last_report);
    core::write_raw(out, m.first_free);
    core::write_raw(out, m.last_free);
    core::write_raw(out, m.ledger);
    core::write_raw(out, m.sp_first);
    core::write_raw(out, m.sp_last);
    core::write_vector(out, m.sp_pairs, 0, m.sp_pairs.size());
    core::write_vector(out, m.wall_springs, 0, m.wall_springs.size());
    core::write_vector(out, m.spring_from, 0, m.spring_from.size());
    core::write_vector(out, m.self_springs.all(), 0, m.self_springs.all().size());
    for (const auto &w : m.window)
      {
        core::write_raw(out, w.injected);
        core::write_raw(out, w.work);
        const std::vector<std::pair<double, double>> steps(w.steps.begin(), w.steps.end());
        core::write_vector(out, steps, 0, steps.size());
      }
    m.save_quasi_static(out);
  }

  void RodModel::load(std::istream &in)
  {
    auto &m = *impl;
    if (core::read_raw<std::uint64_t>(in) != fem_magic)
      throw std::runtime_error("not a checkpoint of the FEM model");
    if (core::read_raw<std::uint64_t>(in) != m.u.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    for (auto *x : {&m.u, &m.v, &m.a, &m.f_old, &m.dissipative_old, &m.friction_old})
      read_dealii_vector(in, *x);
    if (core::peek_vector_size(in) != m.qp.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    core::read_vector(in, m.qp);
    m.t = core::read_raw<double>(in);
    m.dt = core::read_raw<double>(in);
    m.steps = core::read_raw<unsigned long>(in);
    m.cuts = core::read_raw<unsigned long>(in);
    m.overlap_cuts = core::read_raw<unsigned long>(in);
    m.error_cuts = core::read_raw<unsigned long>(in);
    m.last_imbalance = core::read_raw<double>(in);
    m.last_step = core::read_raw<double>(in);
    m.last_report = core::read_raw<core::StepReport>(in);
    m.first_free = core::read_raw<int>(in);
    m.last_free = core::read_raw<int>(in);
    m.ledger = core::read_raw<core::EnergyLedger>(in);
    m.sp_first = core::read_raw<int>(in);
    m.sp_last = core::read_raw<int>(in);
    if (const auto pairs = core::peek_vector_size(in); pairs <= std::size_t{m.n_nodes} * m.n_nodes)
      m.sp_pairs.resize(pairs);
    else
      throw std::runtime_error("checkpoint does not fit this scene");
    core::read_vector(in, m.sp_pairs);
    for (const auto &pr : m.sp_pairs)
      if (pr.i < 0 || pr.j <= pr.i || static_cast<unsigned int>(pr.j) + 1 >= m.n_nodes)
        throw std::runtime_error("checkpoint does not fit this scene");
    // The saved pattern, so that the run orders and rounds as the one it
    // continues.
    if (m.sp_first >= 0)
      m.rebuild_sparsity(m.sp_first, m.sp_last, m.sp_pairs);
    if (core::peek_vector_size(in) != m.wall_springs.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    core::read_vector(in, m.wall_springs);
    if (core::peek_vector_size(in) != m.spring_from.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    core::read_vector(in, m.spring_from);
    for (const auto &w : m.wall_springs)
      if (!std::isfinite(w.elongation))
        throw std::runtime_error("checkpoint holds a non-finite wall spring");
    for (const auto &x : m.spring_from)
      if (!std::isfinite(x.x) || !std::isfinite(x.y))
        throw std::runtime_error("checkpoint holds a non-finite wall spring");
    // The self contacts' springs: a node against a segment of the mesh.
    const auto n_self = core::peek_vector_size(in);
    if (n_self > (m.self_spring ? std::size_t{m.n_nodes} * m.n_nodes : 0))
      throw std::runtime_error("checkpoint does not fit this scene");
    std::vector<PairSpring> self(n_self);
    core::read_vector(in, self);
    for (const auto &p : self)
      if (p.node < 0 || p.node >= m.n_nodes || p.segment < 0 || p.segment + 1 >= m.n_nodes ||
          !std::isfinite(p.elongation) || (p.sliding != 0 && p.sliding != 1))
        throw std::runtime_error("checkpoint holds a self-contact spring that does not fit this scene");
    m.self_springs.commit(std::move(self));
    for (auto &w : m.window)
      {
        w.injected = core::read_raw<double>(in);
        w.work = core::read_raw<double>(in);
        std::vector<std::pair<double, double>> steps(core::peek_vector_size(in));
        core::read_vector(in, steps);
        w.steps.assign(steps.begin(), steps.end());
      }
    m.load_quasi_static(in);
    m.broad.invalidate();
  }

  void RodModel::print_timing(std::ostream &out) const
  {
    impl->timer.print_summary(out);
    out << fmt::format("Newton step cuts: {}\n", impl->cuts);
    out << fmt::format("Newton updates assembled without a tangent, likely to converge: {} ({} did not)\n",
                       impl->tangents_skipped, impl->tangents_missed);
    if (impl->quasi_static_injection)
      out << fmt::format("quasi-static snaps taken by dynamics: {} ({} pushing first; {} dynamic steps)\n",
                         impl->snaps, impl->pushes, impl->dynamic_steps);
    if (impl->overlap_growth > 0)
      out << fmt::format("steps cut for overlap growth (FEM/Overlap growth): {}\n", impl->overlap_cuts);
    if (impl->step_error > 0)
      out << fmt::format("steps cut for their local or energy error (FEM/Step error): {}\n",
                         impl->error_cuts);
    const auto &ls = impl->lu.statistics();
    if (impl->kept_factors || impl->band_solver)
      {
        const bool band = impl->band_solver;
        const auto solves = band ? ls.band_solves : ls.kept_solves;
        const auto iterations = band ? ls.band_iterations : ls.kept_iterations;
        out << fmt::format("GMRES on {}: {} solves, {:.2f} iterations each, {} {}; "
                           "{} steps retried with refactorisation\n",
                           band ? "the band's LU" : "kept factors", solves,
                           solves > 0 ? double(iterations) / double(solves) : 0.0,
                           band ? ls.band_refactorised : ls.kept_refactorised,
                           band ? "solved directly" : "refactorised", impl->retried_steps);
      }
    out << fmt::format(
        "linear solves: {} (patterns analysed {}, full factorisations {}, refactorisations {}, "
        "refactorisations redone for accuracy {}; factors L + U {:.1f} times the matrix's entries)\n",
        ls.solves, ls.analyses, ls.factorisations, ls.refactorisations, ls.inaccurate,
        ls.matrix_entries > 0 ? ls.factor_entries / ls.matrix_entries : 0.0);
  }
} // namespace wirefem::fem
