#include <wirefem/discrete/chain_model.h>
#include <wirefem/discrete/terms.h>
#include <wirefem/core/binary.h>
#include <wirefem/scene/cavity_setup.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace wirefem::discrete
{
  using core::Vec2;
  using injection::Side;

  namespace
  {
    /// The contact law with the coefficients of one kind of contact;
    /// friction is built when mu_st > 0 (or neutral effects are kept).
    ContactLaw with_friction(ContactLaw law, const double mu_static, const double mu_dynamic, const bool keep)
    {
      law.coefficients.mu_static = mu_static;
      law.coefficients.mu_dynamic = mu_dynamic;
      law.friction = keep || mu_static > 0.0;
      return law;
    }
  } // namespace

  ChainModel::ChainModel(const scene::ChainScene &scene)
    : radius(scene.cavity.radius)
    , diameter(1.0)
    , lambda0(scene.discrete.segment_length)
    , k2(scene.wire.bending_stiffness / scene.discrete.segment_length)
    , channels(scene.cavity.radius, scene.injection.speed, scene.injection.ramp_time,
               scene.injection.slow_start_speed, scene.injection.slow_start_length)
  {
    if (scene.setup == scene::Setup::cantilever)
      build_clamped(scene);
    else if (scene.setup == scene::Setup::capstan)
      build_capstan(scene);
    else
      build_injected(scene);
  }

  void ChainModel::build_injected(const scene::ChainScene &scene)
  {
    allocate_injected_chain(scene);
    add_material_terms(scene);
    add_contact_terms(scene);
    dt = stable_time_step(scene.discrete);

    // The perturbed initial wire is not stress free: its energy is energy in.
    // Where it is bent beyond yield it starts plastically pre-bent (the
    // return-mapped state is committed), so its energy in is the elastic
    // energy it actually stores; without the commit the first step would
    // book the excess as plastic dissipation that no work ever paid for.
    StepEnergy e0;
    for (auto &term : terms)
      term->add_forces(nodes, dt, e0);
    for (auto &term : terms)
      term->commit();
    std::fill(nodes.f.begin(), nodes.f.end(), Vec2{});
    std::fill(nodes.contact_force.begin(), nodes.contact_force.end(), 0.0);
    ledger.initial = e0.stretching + e0.bending + e0.contact;
    ledger.stretching = e0.stretching;
    ledger.bending = e0.bending;
    ledger.contact = e0.contact;
  }

  void ChainModel::allocate_injected_chain(const scene::ChainScene &scene)
  {
    const double mass = scene.wire.mass_per_length * lambda0;
    // Storage for every node the run can hold: the wire that fills the
    // cavity up to the maximum packing density, plus the channel nodes.
    // Tangential channels start from an S of two half circles between the
    // inlets (place_initial_wire), n0 whole segments long.
    if (scene.injection.tangential_channels)
      {
        const double r_inlet = radius - 0.5 * diameter;
        channels.make_tangential(r_inlet, std::lround(M_PI * r_inlet / lambda0) * lambda0);
      }
    else if (scene::general_wall(scene.cavity, scene.injection))
      {
        // Any cavity, channels anywhere: the initial wire is the curve
        // between the inlets (or one inlet's stub), n0 whole segments long.
        shaped_wall = scene::channelled_wall(scene.cavity, scene.injection);
        const auto curve = injection::initial_curve(*shaped_wall, lambda0);
        channels.place(shaped_wall->mouths, std::lround(curve.length() / lambda0) * lambda0, curve.turning());
      }
    const int n0 = static_cast<int>(std::lround(channels.initial_length() / lambda0));
    const double max_length = scene.injection.maximum_packing_density * M_PI * radius * radius / diameter;
    // The channels push the wire by its nodes deeper than `hold` inside
    // them; between there and the mouth the channel walls guide it
    // (ChannelTerm), which lets each node go gradually as it leaves.
    hold = std::max(2.0 * lambda0, 2.0 * diameter);
    // Further back beside a tangential inlet or an oblique mouth.
    hold += injection::hold_beyond_mouth(channels.is_tangential(), channels.inlet(Side::right).x, diameter,
                                         scene.injection.channel_angle);
    // (Storage is laid out for both ends; one channel feeds all from the left.)
    const int extra = static_cast<int>(std::ceil(std::max(0.0, max_length - channels.initial_length()) /
                                                 (channels.count() * lambda0))) +
                      static_cast<int>(std::ceil(hold / lambda0)) + 8;
    nodes = Chain(n0 + 1 + 2 * 2 + 2 * extra);
    nodes.lambda0 = lambda0;
    window[0].length = window[1].length = lambda0;
    nodes.node_mass = mass;
    nodes.n_prescribed = 2;
    // One channel: the wire's last node is its free end.
    nodes.n_prescribed_last = channels.pushes(Side::right) ? 2 : 0;
    place_initial_wire(scene);
    feed_channels();
  }

  void ChainModel::add_material_terms(const scene::ChainScene &scene)
  {
    const double k1 = scene.wire.axial_stiffness / lambda0;
    effects.push_back("stretching");
    terms.push_back(std::make_unique<StretchingTerm>(k1, scene.discrete.axial_damping, nodes.capacity()));
    if (scene.wire.bending_stiffness > 0.0)
      {
        const auto &pl = scene.wire.plasticity;
        const double alpha = scene.yield_angle();
        const bool plastic = scene.plastic_bending;
        const auto law = plastic ? material::MomentCurvatureLaw(k2, alpha, pl.hardening_slope, pl.hardening)
                                 : material::MomentCurvatureLaw(k2);
        auto b = std::make_unique<BendingTerm>(law, scene.discrete.rotational_damping, nodes.capacity());
        bending = b.get();
        terms.push_back(std::move(b));
        effects.push_back("bending");
        if (bending->has_plasticity())
          effects.push_back("plasticity");
      }
    if (scene.discrete.translational_damping > 0.0)
      terms.push_back(std::make_unique<DampingTerm>(scene.discrete.translational_damping, nodes.capacity()));
    if (scene.discrete.translational_damping > 0.0 || (bending && scene.discrete.rotational_damping > 0.0))
      effects.push_back("damping");
  }

  void ChainModel::add_contact_terms(const scene::ChainScene &scene)
  {
    const bool keep = scene.keep_neutral_effects;
    const auto &con = scene.contact;
    const auto &fr = con.friction;
    // Penalty per unit wire length: a node (or a segment pair) stands for
    // lambda_0 of wire, so the contact force per length does not depend on
    // the discretisation.
    const double kn = con.normal_stiffness * lambda0;
    ContactLaw law;
    law.diameter = diameter;
    law.normal_stiffness = kn;
    law.coefficients.threshold_velocity = fr.threshold_velocity;
    law.coefficients.tangential_stiffness = fr.tangential_stiffness_ratio * kn;
    law.surface_torque = fr.surface_torque;
    bool any_friction = false;
    if (con.wall_contact)
      {
        const ContactLaw wall =
            with_friction(law, fr.wall_static_coefficient, fr.wall_dynamic_coefficient, keep);
        any_friction |= wall.friction;
        auto w = std::make_unique<WallContactTerm>(radius, wall, nodes.capacity());
        if (channels.is_tangential())
          w->make_channels_tangential();
        if (shaped_wall)
          w->use_shaped_wall(shaped_wall);
        terms.push_back(std::move(w));
        effects.push_back("wall contact");
      }
    if (con.self_contact)
      {
        const ContactLaw self = with_friction(law, fr.static_coefficient, fr.dynamic_coefficient, keep);
        any_friction |= self.friction;
        const int exclusion = std::max(1, static_cast<int>(std::ceil(con.exclusion_length / lambda0 - 1e-9)));
        auto s = std::make_unique<SelfContactTerm>(self, con.skin, exclusion, nodes.capacity());
        self_contact = s.get();
        terms.push_back(std::move(s));
        const double zeta_max = std::min(2.0 * lambda0 / diameter, 2.0 * M_PI / 3.0);
        const double k_limit = 0.25 * kn * lambda0 * lambda0;
        terms.push_back(std::make_unique<CurvatureLimitTerm>(zeta_max, k_limit));
        effects.push_back("self contact");
      }
    if (any_friction)
      effects.push_back("friction");
    if (any_friction && fr.surface_torque)
      effects.push_back("surface torque");
    // The channel walls: as stiff per length as the contact penalty per d.
    const double k_channel = con.normal_stiffness / diameter;
    terms.push_back(std::make_unique<ChannelTerm>(channels, k_channel));
    effects.push_back("inertia");
  }

  double ChainModel::stable_time_step(const scene::DiscreteParameters &dd) const
  {
    if (dd.time_step > 0.0)
      return dd.time_step;
    StabilityBound sum;
    for (const auto &term : terms)
      {
        const auto b = term->stability_bound(nodes.node_mass, lambda0);
        sum.omega2 += b.omega2;
        sum.rate += b.rate;
      }
    return explicit_time_step(dd.time_step_factor, sum.omega2, sum.rate);
  }

  ChainModel::~ChainModel() = default;

  void ChainModel::place_initial_wire(const scene::ChainScene &scene)
  {
    const int n0 = static_cast<int>(std::lround(channels.initial_length() / lambda0));
    const int extra = (nodes.capacity() - (n0 + 1 + 4)) / 2;
    nodes.first = extra;
    left_origin = nodes.first + 1;
    right_origin = left_origin + n0;
    nodes.last = right_origin + 1 + nodes.n_prescribed_last / 2;
    for (int k = nodes.first; k <= left_origin; ++k)
      nodes.x[k] = channels.position(Side::left, (k - left_origin) * lambda0, 0.0);
    for (int k = right_origin; k < nodes.last; ++k)
      nodes.x[k] = channels.position(Side::right, (right_origin - k) * lambda0, 0.0);

    if (channels.is_tangential())
      {
        // The S (injection::Channels::initial_s) with its nodes n0 equal
        // chords apart (a relative prestretch below lambda_0 / (2 pi r'),
        // booked as initial energy).
        const double ds = M_PI * channels.inlet(Side::right).x / n0;
        for (int k = left_origin + 1; k < right_origin; ++k)
          nodes.x[k] = channels.initial_s((k - left_origin) * ds).position;
      }
    else if (shaped_wall)
      {
        // The curve between the inlets (or the stub to the free end) with
        // the seeded perturbation across it, its nodes equally spaced along
        // the curve.
        const auto curve = injection::initial_curve(*shaped_wall, lambda0);
        const double ds = curve.length() / n0;
        const auto &in = scene.injection;
        const auto shape = injection::initial_shape(in.seed, in.perturbation, in.mirror_asymmetry, curve,
                                                    shaped_wall->mouths.size());
        const int end = channels.pushes(Side::right) ? right_origin : right_origin + 1;
        for (int k = left_origin + 1; k < end; ++k)
          nodes.x[k] = curve.perturbed((k - left_origin) * ds, shape);
      }
    else
      {
        // The seeded perturbation (injection/inlet.h).
        const injection::InitialShape shape(scene.injection.seed, scene.injection.perturbation, 2.0 * radius,
                                            scene.injection.mirror_asymmetry);
        for (int k = left_origin + 1; k < right_origin; ++k)
          {
            const double xi = (k - left_origin) * lambda0;
            nodes.x[k] = {xi - radius, shape.offset(xi)};
          }
      }
    for (int k = nodes.first; k < nodes.last; ++k)
      nodes.v[k] = Vec2{}; // the channels start from rest
  }

  void ChainModel::feed_channels()
  {
    const double v = channels.injection_speed(t);
    // The innermost pushed node is released once it is within `hold` of the
    // inlet; a new node enters at the back of the channel, so each channel
    // always pushes two nodes in line.
    while (channels.depth(Side::left, nodes.x[nodes.first + 1]) > -hold)
      {
        if (nodes.first == 0)
          throw std::runtime_error("chain storage exhausted at the left channel");
        const int k = --nodes.first;
        nodes.x[k] = channels.position(Side::left, (k - left_origin) * lambda0, t);
        nodes.v[k] = v * channels.axis(Side::left);
        ledger.injection_work += 0.5 * nodes.node_mass * v * v;
      }
    while (channels.pushes(Side::right) && channels.depth(Side::right, nodes.x[nodes.last - 2]) > -hold)
      {
        if (nodes.last == nodes.capacity())
          throw std::runtime_error("chain storage exhausted at the right channel");
        const int k = nodes.last++;
        nodes.x[k] = channels.position(Side::right, (right_origin - k) * lambda0, t);
        nodes.v[k] = v * channels.axis(Side::right);
        ledger.injection_work += 0.5 * nodes.node_mass * v * v;
      }
  }

  void ChainModel::step()
  {
    if (clamped)
      {
        clamped_forces();
        clamped_advance();
        return;
      }
    if (capstan_loading)
      {
        capstan_step();
        return;
      }
    auto &c = nodes;
    std::fill(c.f.begin() + c.first, c.f.begin() + c.last, Vec2{});
    std::fill(c.contact_force.begin() + c.first, c.contact_force.begin() + c.last, 0.0);
    step_energy = StepEnergy{};
    for (auto &term : terms)
      term->add_forces(c, dt, step_energy);

    // The channel holds its nodes on their prescribed path: it supplies
    // minus the force the wire exerts on them.
    const Vec2 al = channels.axis(Side::left), ar = channels.axis(Side::right);
    inlet_force[0] = -dot(c.f[c.first] + c.f[c.first + 1], al);
    inlet_force[1] = channels.pushes(Side::right) ? -dot(c.f[c.last - 1] + c.f[c.last - 2], ar) : 0.0;
    // Work of the channels over the step: force times the exact injected length.
    const double du = channels.injected_per_channel(t + dt) - channels.injected_per_channel(t);
    ledger.injection_work += (inlet_force[0] + inlet_force[1]) * du;
    window[0].add(du, inlet_force[0] * du);
    window[1].add(du, inlet_force[1] * du);

    const double inv_m = 1.0 / c.node_mass;
    double kinetic = 0.0;
    // Velocities live at half steps (v is v_{n-1/2} before the update and
    // v_{n+1/2} after), so the kinetic energy at step n that the scheme
    // conserves to second order with the potentials at x_n is
    // 1/2 m v_{n-1/2} . v_{n+1/2}.
    for (int k = c.first + c.n_prescribed; k < c.last - c.n_prescribed_last; ++k)
      {
        const Vec2 v_old = c.v[k];
        c.v[k] += (dt * inv_m) * c.f[k];
        c.x[k] += dt * c.v[k];
        kinetic += 0.5 * c.node_mass * dot(v_old, c.v[k]);
      }
    t += dt;
    ++steps;
    const double vt = channels.injection_speed(t);
    for (int k = c.first; k < c.first + c.n_prescribed; ++k)
      {
        c.x[k] = channels.position(Side::left, (k - left_origin) * lambda0, t);
        c.v[k] = vt * al;
      }
    for (int k = c.last - c.n_prescribed_last; k < c.last; ++k)
      {
        c.x[k] = channels.position(Side::right, (right_origin - k) * lambda0, t);
        c.v[k] = vt * ar;
      }
    feed_channels();
    for (auto &term : terms)
      term->commit();

    ledger.stretching = step_energy.stretching;
    ledger.bending = step_energy.bending;
    ledger.contact = step_energy.contact;
    ledger.kinetic = kinetic;
    ledger.plastic += step_energy.plastic_work;
    ledger.damping += step_energy.damping_work;
    ledger.friction += step_energy.friction_work;
    ledger.friction_stored = step_energy.friction_stored;
  }

  namespace
  {
    constexpr std::uint64_t checkpoint_magic = 0x77697265666d3033ull; // "wirefm03"
  }

  void ChainModel::save(std::ostream &out) const
  {
    core::write_raw(out, checkpoint_magic);
    core::write_raw(out, nodes.capacity());
    core::write_raw(out, left_origin);
    core::write_raw(out, dt);
    core::write_raw(out, static_cast<std::uint64_t>(terms.size()));
    core::write_raw(out, nodes.first);
    core::write_raw(out, nodes.last);
    core::write_raw(out, t);
    core::write_raw(out, steps);
    core::write_raw(out, inlet_force);
    core::write_raw(out, ledger);
    core::write_raw(out, step_energy);
    core::write_vector(out, nodes.x, nodes.first, nodes.last);
    core::write_vector(out, nodes.v, nodes.first, nodes.last);
    for (const auto &w : window)
      {
        const std::vector<std::pair<double, double>> steps(w.steps.begin(), w.steps.end());
        core::write_vector(out, steps, 0, steps.size());
        core::write_raw(out, w.injected);
        core::write_raw(out, w.work);
      }
    for (const auto &term : terms)
      term->save(out);
  }

  void ChainModel::load(std::istream &in)
  {
    if (core::read_raw<std::uint64_t>(in) != checkpoint_magic)
      throw std::runtime_error("not a wirefem checkpoint of this version");
    const auto capacity = core::read_raw<int>(in);
    const auto origin = core::read_raw<int>(in);
    const auto step = core::read_raw<double>(in);
    const auto n_terms = core::read_raw<std::uint64_t>(in);
    if (capacity != nodes.capacity() || origin != left_origin || step != dt || n_terms != terms.size())
      throw std::runtime_error("the checkpoint was written for a different scene");
    nodes.first = core::read_raw<int>(in);
    nodes.last = core::read_raw<int>(in);
    t = core::read_raw<double>(in);
    steps = core::read_raw<unsigned long>(in);
    const auto forces = core::read_raw<std::array<double, 2>>(in);
    inlet_force[0] = forces[0];
    inlet_force[1] = forces[1];
    ledger = core::read_raw<EnergyLedger>(in);
    step_energy = core::read_raw<StepEnergy>(in);
    core::read_vector(in, nodes.x);
    core::read_vector(in, nodes.v);
    for (auto &w : window)
      {
        std::vector<std::pair<double, double>> steps(core::peek_vector_size(in));
        core::read_vector(in, steps);
        w.steps.assign(steps.begin(), steps.end());
        w.injected = core::read_raw<double>(in);
        w.work = core::read_raw<double>(in);
      }
    for (auto &term : terms)
      term->load(in);
  }

  bool ChainModel::finite() const
  {
    for (int k = nodes.first; k < nodes.last; ++k)
      if (!std::isfinite(nodes.x[k].x) || !std::isfinite(nodes.x[k].y) || !std::isfinite(nodes.v[k].x) ||
          !std::isfinite(nodes.v[k].y))
        return false;
    return true;
  }

  core::WireState ChainModel::wire_state() const
  {
    core::WireState w;
    w.diameter = diameter;
    w.cavity_radius = radius;
    if (shaped_wall)
      shaped_wall->describe(w);
    w.time = t;
    w.injected_length = injected_length();
    // The nodes at the inlets (one channel: the last is the free end).
    const int k0 = nodes.first + 1, k1 = nodes.last - 1 - nodes.n_prescribed_last / 2;
    const int n = k1 - k0 + 1;
    w.resize(n);
    for (int k = k0; k <= k1; ++k)
      {
        const int p = k - k0;
        w.points[p] = nodes.x[k];
        w.arc_length[p] = p * lambda0;
        w.contact_force[p] = nodes.contact_force[k];
        if (bending)
          {
            const double zeta = BendingTerm::turning_angle(nodes, k);
            const double zp = bending->plastic_angle(k);
            w.curvature[p] = zeta / lambda0;
            w.plastic_curvature[p] = zp / lambda0;
            w.bending_energy[p] = 0.5 * k2 * (zeta - zp) * (zeta - zp);
          }
      }
    if (self_contact)
      for (const auto &a : self_contact->active_pairs())
        {
          core::SelfContact sc;
          sc.s_a = (a.i - k0 + a.s) * lambda0;
          sc.s_b = (a.j - k0 + a.t) * lambda0;
          sc.point_a = std::clamp(static_cast<int>(std::lround(a.i - k0 + a.s)), 0, n - 1);
          sc.point_b = std::clamp(static_cast<int>(std::lround(a.j - k0 + a.t)), 0, n - 1);
          sc.x_a = (1.0 - a.s) * nodes.x[a.i] + a.s * nodes.x[a.i + 1];
          sc.x_b = (1.0 - a.t) * nodes.x[a.j] + a.t * nodes.x[a.j + 1];
          sc.normal_force = a.normal_force;
          w.self_contacts.push_back(sc);
        }
    return w;
  }
} // namespace wirefem::discrete

#include <fmt/format.h>

namespace wirefem::discrete
{
  std::string ChainModel::description() const
  {
    if (clamped)
      return fmt::format("{} segments, dt = {:.4g}, drag gamma = {:.4g}", nodes.last - 1, dt, drag);
    return fmt::format("lambda_0 = {}, dt = {:.4g} (explicit)", lambda0, dt);
  }
} // namespace wirefem::discrete
