#include "rod_model_impl.h"

#include <wirefem/scene/cavity_setup.h>

#include <tuple>

namespace wirefem::fem
{
  RodModel::Impl::Impl(const scene::RodScene &s)
    : scene(s)
    , radius(s.cavity.radius)
    , diameter(1.0)
    , rhoA(s.wire.mass_per_length)
    , rhoI(s.wire.mass_per_length * diameter * diameter / 16.0)
    , channels(s.cavity.radius, s.injection.speed, s.injection.ramp_time, s.injection.slow_start_speed,
               s.injection.slow_start_length)
    , p(s.fem.degree)
    , h(s.fem.element_length)
    , fe(dealii::FE_Q<1, 2>(s.fem.degree), 3)
    , broad(1.0, s.contact.skin, 1)
  {
    // The clamp loading (Set-up = cantilever) has no cavity to touch.
    clamped = s.setup == scene::Setup::cantilever;
    if (clamped)
      scene.contact.wall_contact = scene.contact.self_contact = false;
    // The capstan: the wall with friction, nothing else.
    capstan = s.setup == scene::Setup::capstan;
    if (capstan)
      {
        scene.contact.wall_contact = true;
        scene.contact.self_contact = false;
      }
    build_mesh(scene);
    build_physics(scene);
    set_initial_state(scene);
    if (wall_spring)
      note_spring_positions(u);
    if (quasi_static_injection)
      relax_start();
  }

  void RodModel::Impl::relax_start()
  {
    // The start shape is bent stress-free but lies over a straight chord,
    // so it is stretched. Without inertia that stretch would relax within
    // the first step, and the step's numerical dissipation would take its
    // energy unbooked. It relaxes here instead, in steps that end at t = 0
    // (the channels held), until its stored energy settles; the ledger
    // opens after, with that energy as the initial one.
    double before = ledger.initial;
    for (int i = 0; i < 20; ++i)
      {
        t = -dt_max;
        const bool ok = solve_step(dt_max) == StepOutcome::converged;
        t = 0.0;
        if (!ok)
          throw std::runtime_error("the quasi-static start shape did not relax (Newton failed)");
        const double now = ledger.stored();
        const bool settled = std::abs(now - before) <= 1e-6 * std::max(now, 1e-12);
        before = now;
        if (settled)
          break;
      }
    core::EnergyLedger opened;
    opened.stretching = ledger.stretching;
    opened.shear = ledger.shear;
    opened.bending = ledger.bending;
    opened.contact = ledger.contact;
    opened.initial = ledger.stored();
    ledger = opened;
    for (auto &w : window)
      w = injection::ForceWindow{w.length, {}, 0.0, 0.0};
    steps = 0;
    v = 0.0;
    a = 0.0;
    // The step control's memory starts afresh with the ledger.
    last_step = last_imbalance = 0.0;
  }

  void RodModel::Impl::note_spring_positions(const dealii::Vector<double> &at)
  {
    spring_from.resize(n_wall_sites());
    if (segment_points.empty())
      for (unsigned int k = 0; k < n_nodes; ++k)
        spring_from[k] = position(at, k);
    else
      for (unsigned int k = 0, i = 0; k + 1 < n_nodes; ++k)
        for (const auto &cp : segment_points[k])
          spring_from[i++] = point_position(at, cp);
  }

  void RodModel::Impl::build_mesh(const scene::RodScene &s)
  {
    if (clamped)
      {
        // The rod of length L, from the clamp at S = 0.
        const double L = s.cantilever.length;
        n_cells = std::max(1u, static_cast<unsigned int>(std::lround(L / s.fem.element_length)));
        h = L / n_cells;
        a_left = 0.0;
        a_right = L;
      }
    else if (capstan)
      build_capstan_mesh(s);
    else
      build_channel_mesh(s);
    make_mesh();
  }

  void RodModel::Impl::build_channel_mesh(const scene::RodScene &s)
  {
    // The wire the channels can ever push in: phi_max pi r^2 inside, plus
    // two elements of margin in each channel.
    const double L_max = s.injection.maximum_packing_density * M_PI * radius * radius / diameter;
    hold = std::max(2.0 * h, 2.0 * diameter);
    // Tangential channels start from an S of two half circles between the
    // inlets, L0 = pi r' long (not rounded: the mesh need not end at the
    // inlets).
    const double r_inlet = radius - 0.5 * diameter;
    if (s.injection.tangential_channels)
      channels.make_tangential(r_inlet, M_PI * r_inlet);
    else if (scene::general_wall(s.cavity, s.injection))
      {
        // Any cavity, channels anywhere: the initial wire is the curve
        // between the inlets (not rounded). One channel's stub is whole
        // elements long, so that the mesh ends at its free end.
        wall_settings.shaped = scene::channelled_wall(s.cavity, s.injection);
        const auto curve = injection::initial_curve(*wall_settings.shaped, h);
        channels.place(wall_settings.shaped->mouths, curve.length(), curve.turning());
      }
    // As in the discrete model: further back beside a tangential inlet or
    // an oblique mouth.
    hold += injection::hold_beyond_mouth(s.injection.tangential_channels, r_inlet, diameter,
                                         s.injection.channel_angle);
    const double L0 = channels.initial_length();
    k_channel = s.contact.normal_stiffness / diameter;
    const unsigned int n_pushing = static_cast<unsigned int>(channels.count());
    const double per_channel = (L_max - L0) / n_pushing + 2.0 * h + hold;
    const unsigned int n_channel = static_cast<unsigned int>(std::ceil(per_channel / h));
    const unsigned int n_cavity = static_cast<unsigned int>(std::ceil(L0 / h - 1e-9));
    n_cells = n_pushing * n_channel + n_cavity;
    a_left = n_channel * h;
    a_right = a_left + L0;
  }

  void RodModel::Impl::make_mesh()
  {
    std::vector<dealii::Point<2>> vertices(n_cells + 1);
    for (unsigned int i = 0; i <= n_cells; ++i)
      vertices[i] = dealii::Point<2>(i * h, 0.0);
    std::vector<dealii::CellData<1>> cells(n_cells);
    for (unsigned int i = 0; i < n_cells; ++i)
      {
        cells[i].vertices[0] = i;
        cells[i].vertices[1] = i + 1;
      }
    tria.create_triangulation(vertices, cells, dealii::SubCellData());
    dof_handler.reinit(tria);
    dof_handler.distribute_dofs(fe);
    n_local = fe.n_dofs_per_cell();
    n_nodes = n_cells * p + 1;

    // Number the dofs node by node along the wire, (x, y, theta) per node,
    // so that the free nodes between the inlets are one contiguous block.
    std::vector<dealii::types::global_dof_index> renumber(dof_handler.n_dofs());
    std::vector<dealii::types::global_dof_index> local(n_local);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int k = static_cast<unsigned int>(std::lround(cell->vertex(0)[0] / h));
        cell->get_dof_indices(local);
        for (unsigned int i = 0; i < n_local; ++i)
          {
            const auto ci = fe.system_to_component_index(i);
            const unsigned int a_ = ci.second;
            const unsigned int node = a_ == 0 ? k * p : a_ == 1 ? (k + 1) * p : k * p + (a_ - 1);
            renumber[local[i]] = 3 * node + ci.first;
          }
      }
    dof_handler.renumber_dofs(renumber);
    cell_node.assign(n_cells, std::vector<unsigned int>(p + 1));
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int k = static_cast<unsigned int>(std::lround(cell->vertex(0)[0] / h));
        cell->get_dof_indices(local);
        for (unsigned int i = 0; i < n_local; ++i)
          {
            const auto ci = fe.system_to_component_index(i);
            if (local[i] % 3 != ci.first)
              throw std::logic_error("RodModel: unexpected dof numbering");
            cell_node[k][ci.second] = static_cast<unsigned int>(local[i] / 3);
          }
      }

    stiffness_shape = ElementShape::lagrange(p, h, p); // reduced: p Gauss points
    mass_shape = ElementShape::lagrange(p, h, p + 1);
    node_S.resize(n_nodes);
    for (unsigned int c = 0; c < n_cells; ++c)
      for (unsigned int a_ = 0; a_ <= p; ++a_)
        node_S[cell_node[c][a_]] = (c + stiffness_shape.node_position[a_]) * h;
    min_spacing = h;
    for (unsigned int k = 0; k + 1 < n_nodes; ++k)
      min_spacing = std::min(min_spacing, node_S[k + 1] - node_S[k]);

    element_mass.assign(9 * (p + 1) * (p + 1), 0.0);
    const unsigned int nd = 3 * (p + 1);
    for (unsigned int q = 0; q < mass_shape.n_q; ++q)
      for (unsigned int i = 0; i <= p; ++i)
        for (unsigned int j = 0; j <= p; ++j)
          for (unsigned int c = 0; c < 3; ++c)
            element_mass[(3 * i + c) * nd + 3 * j + c] += mass_shape.weight[q] * mass_shape.value(q, i) *
                                                          mass_shape.value(q, j) * (c < 2 ? rhoA : rhoI);
    lumped_element.assign(nd, 0.0);
    for (unsigned int i = 0; i < nd; ++i)
      for (unsigned int j = 0; j < nd; ++j)
        lumped_element[i] += element_mass[i * nd + j];
  }

  void RodModel::Impl::build_physics(const scene::RodScene &s)
  {
    build_material(s);
    build_contact(s);
    build_integrator(s);
  }

  void RodModel::Impl::build_material(const scene::RodScene &s)
  {
    const auto &w = s.wire;
    section.EA = w.axial_stiffness;
    section.GA = s.fem.formulation == scene::Formulation::kirchhoff
                     ? s.fem.kirchhoff_penalty * w.axial_stiffness
                     : s.fem.shear_stiffness;
    section.axial_viscosity = s.fem.axial_viscosity;
    section.bending_viscosity = s.fem.bending_viscosity;
    if (clamped || capstan)
      section.axial_viscosity = section.bending_viscosity = 0.0;
    viscous = section.axial_viscosity > 0 || section.bending_viscosity > 0;
    drag = clamped || capstan ? 0.0 : s.fem.translational_damping;
    const auto &pl = w.plasticity;
    plastic = s.plastic_bending;
    law = plastic ? material::MomentCurvatureLaw(w.bending_stiffness, pl.yield_curvature, pl.hardening_slope,
                                                 pl.hardening)
                  : material::MomentCurvatureLaw(w.bending_stiffness);

    effects = {"stretching",
               s.fem.formulation == scene::Formulation::kirchhoff ? "shear constraint" : "shear"};
    if (w.bending_stiffness > 0)
      effects.push_back("bending");
    if (plastic)
      effects.push_back("plasticity");
    if (viscous || drag > 0)
      effects.push_back("damping");
  }

  void RodModel::Impl::build_contact(const scene::RodScene &s)
  {
    const bool keep = s.keep_neutral_effects;
    const auto &con = s.contact;
    const auto &fr = con.friction;
    ContactSettings base;
    base.diameter = diameter;
    base.stiffness = con.normal_stiffness;
    base.threshold_velocity = fr.threshold_velocity;
    const auto shaped = wall_settings.shaped; // build_channel_mesh's
    wall_settings = self_settings = base;
    wall_settings.shaped = shaped;
    wall_settings.mu_static = fr.wall_static_coefficient;
    wall_settings.mu_dynamic = fr.wall_dynamic_coefficient;
    wall_settings.friction = con.wall_contact && (keep || fr.wall_static_coefficient > 0 || capstan);
    wall_settings.mouths = !channels.is_tangential(); // the capstan's cavity has the radial channels too
    wall_spring = s.fem.spring_friction;
    self_settings.stiffness = con.normal_stiffness * s.fem.self_contact_stiffness;
    self_settings.mu_static = fr.static_coefficient;
    self_settings.mu_dynamic = fr.dynamic_coefficient;
    self_settings.friction = con.self_contact && (keep || fr.static_coefficient > 0);
    self_spring = s.fem.spring_self_friction && self_settings.friction;
    if (con.wall_contact)
      effects.push_back("wall contact");
    if (con.self_contact)
      effects.push_back("self contact");
    if (wall_settings.friction || self_settings.friction)
      effects.push_back("friction");
    exclusion = std::max(1, static_cast<int>(std::ceil(con.exclusion_length / min_spacing - 1e-9)));
    // K's pattern holds the pairs within pattern_margin of contact; the
    // broad phase finds all of them (its guarantee reaches the contact
    // distance plus the margin; its cutoff, diameter + skin, is unchanged).
    pattern_margin = 0.2 * con.skin;
    broad = contact::BroadPhase(diameter + pattern_margin, con.skin - pattern_margin, exclusion);
    if (con.self_contact || con.wall_contact)
      set_up_contact_points(s.fem.contact_points);
    wall_springs.assign(wall_spring ? n_wall_sites() : 0, contact::FrictionHistory{});
  }

  void RodModel::Impl::set_generalized_alpha(const double rho)
  {
    // Kept for the dynamic phases of quasi-static injection too.
    dyn_alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
    dyn_alpha_f = rho / (rho + 1.0);
    dyn_gamma = 0.5 - dyn_alpha_m + dyn_alpha_f;
    dyn_beta = 0.25 * (1.0 - dyn_alpha_m + dyn_alpha_f) * (1.0 - dyn_alpha_m + dyn_alpha_f);
  }

  void RodModel::Impl::use_alpha(const bool generalized)
  {
    alpha_m = generalized ? dyn_alpha_m : 0.0;
    alpha_f = generalized ? dyn_alpha_f : 0.0;
    beta = generalized ? dyn_beta : 0.25;
    gamma = generalized ? dyn_gamma : 0.5;
  }

  namespace
  {
    /// The stiffer of the wall's and the wire-wire contacts' penalties per
    /// length: it sets the shortest contact period.
    double stiffest_contact(const scene::RodScene &s)
    {
      return s.contact.normal_stiffness * std::max(1.0, s.fem.self_contact_stiffness);
    }
  } // namespace

  double RodModel::Impl::default_step(const scene::RodScene &s) const
  {
    // Quasi-static injection steps by injected length: 0.025 d a step,
    // whatever the speed (no inertia, so no contact period to resolve).
    if (quasi_static_injection)
      return 0.025 * diameter / s.injection.speed;
    return dynamic_step(s);
  }

  double RodModel::Impl::dynamic_step(const scene::RodScene &s) const
  {
    // FEM/Step error: the local error estimate sets the step, under a cap
    // ten times as long and not tied to the contact period.
    if (step_error > 0)
      return std::min(0.25, 0.25 * diameter / s.injection.speed);
    // At most a fifth of a contact's period 2 pi sqrt(rho A / k_n) too (0.028
    // at the default k_n; at 10 k_n the ledger closes to 5e-4, not 2.3%).
    const double contact_step = 0.4 * M_PI * std::sqrt(rhoA / stiffest_contact(s));
    return std::min({0.025, 0.025 * diameter / s.injection.speed, contact_step});
  }

  namespace
  {
    /// kept_factors and band_solver for FEM/Linear solver. The band (and
    /// auto) only with generalized-alpha: without the mass term it is a
    /// poor preconditioner (quasi-static classic scene at f = 15: 27 GMRES
    /// iterations a solve, most solves ending in an LU, 3 times the time).
    /// With its own LU the band costs less than an LU of the tangent at any
    /// size (docs/notes/2026-12-06-band-lu.md), so auto is the band there.
    /// The snaps of quasi-static injection keep the LU: on the band GMRES
    /// took 13-17 iterations a solve there, and the solves cost more
    /// (docs/notes/2026-12-06-contact-prefilter.md).
    std::pair<bool, bool> linear_solver_choice(const scene::LinearSolver solver,
                                               const scene::Integrator integrator)
    {
      const bool dynamic = integrator == scene::Integrator::generalized_alpha;
      return {solver == scene::LinearSolver::kept_factors,
              dynamic && (solver == scene::LinearSolver::automatic || solver == scene::LinearSolver::band)};
    }

    /// FEM/Newton tolerance, relative to the force scale; 0: 1e-6 under
    /// generalized-alpha, whose steps' own error is far larger (on the
    /// classic scene at f = 25 a fifth fewer Newton iterations than 1e-8,
    /// phi at jamming and loops within the seed spread:
    /// docs/notes/2026-12-07-newton-slow-iterations.md), 1e-8 where each
    /// step is an equilibrium (quasi-static steps, the capstan).
    double newton_tolerance_of(const double key, const scene::Integrator integrator)
    {
      if (key > 0)
        return key;
      return integrator == scene::Integrator::generalized_alpha ? 1e-6 : 1e-8;
    }
  } // namespace

  void RodModel::Impl::build_integrator(const scene::RodScene &s)
  {
    const auto &w = s.wire;
    if (clamped)
      effects.push_back("end load");
    if (capstan)
      effects.push_back("end loads");
    const auto integrator = clamped || capstan ? scene::Integrator::quasi_static : s.fem.integrator;
    inertia = integrator != scene::Integrator::quasi_static;
    quasi_static_injection = !inertia && !clamped && !capstan;
    newton_tolerance = newton_tolerance_of(s.fem.newton_tolerance, integrator) * w.axial_stiffness;
    std::tie(kept_factors, band_solver) = linear_solver_choice(
        clamped || capstan ? scene::LinearSolver::refactorise : s.fem.linear_solver, integrator);
    // Its reused factors must come from direct solves of this step.
    modified_newton = s.fem.modified_newton && !kept_factors && !band_solver && !clamped && !capstan;
    newton_contraction = s.fem.newton_contraction;
    velocity_predictor = s.fem.velocity_predictor;
    overlap_growth = clamped || capstan ? 0.0 : s.fem.overlap_growth;
    // The error control steps generalized-alpha runs only: not the
    // explicit integrator's stability-limited step, the load steps of the
    // quasi-static set-ups, nor the snaps of quasi-static injection (at
    // f = 25 it made them dearer and moved phi at jamming up), unless
    // those have no dashpots: then the snaps carry the rearrangements,
    // and with fixed steps the ledger missed 2-3%.
    const bool snaps_controlled = quasi_static_injection && !s.fem.quasi_static_dashpots;
    step_error =
        integrator == scene::Integrator::generalized_alpha || snaps_controlled ? s.fem.step_error : 0.0;
    step_energy_error = s.fem.step_energy_error;
    if (clamped)
      {
        force_scale = s.cantilever.force_scale(w.bending_stiffness);
        newton_tolerance = s.cantilever.tolerance * force_scale;
        line_search = false;
      }
    if (capstan)
      {
        // Full Newton steps, on the scale of the end force.
        force_scale = s.capstan.end_force;
        newton_tolerance = newton_tolerance_of(s.fem.newton_tolerance, integrator) * force_scale;
        line_search = false;
      }
    if (inertia)
      effects.push_back("inertia");

    set_generalized_alpha(s.fem.spectral_radius);
    use_alpha(integrator == scene::Integrator::generalized_alpha);
    dt_max = s.fem.time_step > 0 ? s.fem.time_step : default_step(s);
    qs_dt_max = dt_max;

    dynamic_dt_max = s.fem.time_step > 0 ? std::min(s.fem.time_step, dynamic_step(s)) : dynamic_step(s);
    if (integrator == scene::Integrator::explicit_lumped)
      {
        // Central differences (symplectic Euler) with the row-sum lumped
        // mass: stable below 2 / omega_max; half of it by default.
        explicit_mode = true;
        const double hm = min_spacing;
        const double m_t = rhoA * hm, m_r = rhoI * hm;
        const double w2 = std::max(4.0 * (section.EA + section.GA) / (m_t * hm),
                                   (section.GA * hm + 4.0 * w.bending_stiffness / hm) / m_r) +
                          4.0 * stiffest_contact(s) * hm / m_t;
        // A third of the limit: the first-order ledger closes to 0.7% (quick).
        dt_max = s.fem.time_step > 0 ? s.fem.time_step : (1.0 / 3.0) * 2.0 / std::sqrt(w2);
      }
    if (capstan)
      {
        // A step moves the trailing end by at most a fifth of a node spacing
        // (velocity control) or raises the push by at most 1% of the end
        // force (force control).
        const auto &cs = s.capstan;
        dt_max = s.fem.time_step > 0.0 ? s.fem.time_step
                 : cap.velocity        ? 0.2 * (h / p) / cs.speed
                                       : 0.01 / cs.force_rate;
        if (cs.ramp_time > 0.0)
          dt_max = std::min(dt_max, 0.05 * cs.ramp_time);
      }
    dt = dt_max;
    for (int side = 0; side < 2; ++side)
      window[side].length = h / p;
  }

  void RodModel::Impl::nodes_between(const double sl, const double sr, int &first, int &last) const
  {
    first = static_cast<int>(std::upper_bound(node_S.begin(), node_S.end(), sl + 1e-12 * h) - node_S.begin());
    last = static_cast<int>(std::lower_bound(node_S.begin(), node_S.end(), sr - 1e-12 * h) - node_S.begin());
  }

  void RodModel::Impl::free_range(const double time, int &first, int &last) const
  {
    if (clamped || capstan)
      {
        // The clamp holds node 0; so does the capstan's held trailing end.
        first = clamped || (cap.velocity && !cap.roller) ? 1 : 0;
        last = static_cast<int>(n_nodes);
        return;
      }
    nodes_between(left_inlet_S(time) - hold, right_inlet_S(time) + hold, first, last);
    // One channel: the wire is free through its last node.
    const bool free_end = !channels.pushes(Side::right);
    if (free_end)
      last = static_cast<int>(n_nodes);
    if (first < 1 || (!free_end && last >= static_cast<int>(n_nodes)))
      throw std::runtime_error("the wire in the channels is used up (Injection/Maximum packing density "
                               "sets how much wire the mesh holds)");
  }

  void RodModel::Impl::inside_range(const double time, int &first, int &last) const
  {
    if (clamped || capstan)
      {
        first = 0;
        last = static_cast<int>(n_nodes);
        return;
      }
    nodes_between(left_inlet_S(time), right_inlet_S(time), first, last);
    if (!channels.pushes(Side::right))
      last = static_cast<int>(n_nodes);
  }

  void RodModel::Impl::prescribe(const double time, dealii::Vector<double> &x, dealii::Vector<double> *vel,
                                 dealii::Vector<double> *acc, const int first, const int last) const
  {
    if (capstan)
      {
        // Velocity control with the trailing end held: node 0 on the wall's
        // centreline where the push has taken it.
        if (first > 0)
          {
            const double angle = cap.a0 - scene.capstan.pushed(time) / cap.Rc;
            x[0] = cap.Rc * std::cos(angle);
            x[1] = cap.Rc * std::sin(angle);
            x[2] = angle - 0.5 * M_PI;
          }
        return;
      }
    if (clamped)
      {
        // The clamp: node 0 at the origin, its section along +x, at rest.
        for (unsigned int c = 0; c < 3; ++c)
          {
            x[c] = 0.0;
            if (vel)
              (*vel)[c] = 0.0;
            if (acc)
              (*acc)[c] = 0.0;
          }
        return;
      }
    const double speed = injecting() ? channels.injection_speed(injection_time(time)) : 0.0;
    const double accel = injecting() ? channels.injection_acceleration(injection_time(time)) : 0.0;
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        const int ki = static_cast<int>(k);
        if (ki >= first && ki < last)
          continue;
        const Side side = ki < first ? Side::left : Side::right;
        const double m = side == Side::left ? node_S[k] - a_left : a_right - node_S[k];
        const Vec2 pos = channels.position(side, m, injection_time(time));
        const Vec2 axis = channels.axis(side);
        x[3 * k] = pos.x;
        x[3 * k + 1] = pos.y;
        x[3 * k + 2] = channels.wire_angle(side);
        if (vel)
          {
            (*vel)[3 * k] = speed * axis.x;
            (*vel)[3 * k + 1] = speed * axis.y;
            (*vel)[3 * k + 2] = 0.0;
          }
        if (acc)
          {
            (*acc)[3 * k] = accel * axis.x;
            (*acc)[3 * k + 1] = accel * axis.y;
            (*acc)[3 * k + 2] = 0.0;
          }
      }
  }
} // namespace wirefem::fem
