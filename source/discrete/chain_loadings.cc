// The loadings of the chain other than the injection: the clamp (Set-up =
// cantilever) and the capstan (Set-up = capstan). The injection is in
// chain_model.cc.
#include <wirefem/discrete/chain_model.h>
#include <wirefem/discrete/terms.h>

#include <algorithm>
#include <cmath>

namespace wirefem::discrete
{
  using core::Vec2;

  namespace
  {
    Vec2 on_circle(const double radius, const double angle)
    {
      return {radius * std::cos(angle), radius * std::sin(angle)};
    }
  } // namespace

  void ChainModel::build_clamped(const scene::ChainScene &scene)
  {
    clamped = true;
    cantilever = scene.cantilever;
    const auto &w = scene.wire;
    const double L = cantilever.length;
    const int n = static_cast<int>(std::lround(L / lambda0));
    const double k1 = w.axial_stiffness / lambda0;
    const double mass = w.mass_per_length * lambda0;
    nodes = Chain(n + 1);
    nodes.lambda0 = lambda0;
    nodes.node_mass = mass;
    nodes.first = 0;
    nodes.last = n + 1;
    nodes.n_prescribed = nodes.n_prescribed_last = 1;
    for (int k = 0; k <= n; ++k)
      nodes.x[k] = {k * lambda0, 0.0};

    // The same choice of law as the injection; the clamp's spring stands
    // for the half segment next to it (ClampTerm).
    const auto &pl = w.plasticity;
    const double alpha = scene.yield_angle();
    const bool plastic = scene.plastic_bending;
    const auto law = plastic ? material::MomentCurvatureLaw(k2, alpha, pl.hardening_slope, pl.hardening)
                             : material::MomentCurvatureLaw(k2);
    const auto clamp_law =
        plastic ? material::MomentCurvatureLaw(2.0 * k2, 0.5 * alpha, pl.hardening_slope, pl.hardening)
                : material::MomentCurvatureLaw(2.0 * k2);
    terms.push_back(std::make_unique<StretchingTerm>(k1));
    auto b = std::make_unique<BendingTerm>(law, 0.0, n + 1);
    bending = b.get();
    terms.push_back(std::move(b));
    terms.push_back(std::make_unique<ClampTerm>(clamp_law, Vec2{1.0, 0.0}));
    auto load = std::make_unique<EndLoadTerm>(Vec2{cantilever.end_force_x, cantilever.end_force_y},
                                              cantilever.end_moment);
    end_load = load.get();
    terms.push_back(std::move(load));
    effects = {"stretching", "bending"};
    if (plastic)
      effects.push_back("plasticity");
    effects.push_back("end load");

    // The drag is mass proportional, so every mode decays at drag/2 (the
    // first critically by default).
    dt = stable_time_step(scene.discrete);
    const double omega1 = 3.5160 * std::sqrt(w.bending_stiffness / (w.mass_per_length * L * L * L * L));
    drag = cantilever.damping > 0.0 ? cantilever.damping : 2.0 * omega1;
    force_scale = cantilever.force_scale(w.bending_stiffness);
  }

  double ChainModel::clamped_forces()
  {
    auto &c = nodes;
    end_load->set_load_factor(load_factor);
    std::fill(c.f.begin(), c.f.end(), Vec2{});
    step_energy = StepEnergy{};
    for (auto &term : terms)
      term->add_forces(c, dt, step_energy);
    double fmax = 0.0;
    for (int k = c.first + 1; k < c.last; ++k)
      fmax = std::max(fmax, norm(c.f[k]));
    ledger.stretching = step_energy.stretching;
    ledger.bending = step_energy.bending;
    return fmax;
  }

  void ChainModel::clamped_advance()
  {
    auto &c = nodes;
    const double a = 0.5 * drag * dt;
    const double inv_m = 1.0 / c.node_mass;
    for (int k = c.first + 1; k < c.last; ++k)
      {
        c.v[k] = (1.0 / (1.0 + a)) * ((1.0 - a) * c.v[k] + (dt * inv_m) * c.f[k]);
        c.x[k] += dt * c.v[k];
      }
    for (auto &term : terms)
      term->commit();
    ledger.plastic += step_energy.plastic_work;
    t += dt;
    ++steps;
  }

  core::Equilibrium ChainModel::equilibrate(const double target)
  {
    if (!clamped)
      return core::Model::equilibrate(target);
    const double ramp = cantilever.load_time / cantilever.points_per_leg;
    const double from = load_factor, t_leg = t;
    core::Equilibrium out;
    while (true)
      {
        load_factor = ramp > 0.0 && t - t_leg < ramp ? from + (target - from) * (t - t_leg) / ramp : target;
        const double fmax = clamped_forces();
        out.residual = fmax / force_scale;
        if (load_factor == target && out.residual < cantilever.tolerance)
          {
            out.converged = true;
            break;
          }
        if (t >= cantilever.maximum_time || !std::isfinite(fmax))
          break;
        clamped_advance();
      }
    const auto &c = nodes;
    const int n = c.last - 1;
    out.tip_x = c.x[n].x;
    out.tip_y = c.x[n].y;
    // The last segment's direction is the rod's at its midpoint; half the
    // last turning angle carries it to the end.
    out.tip_rotation = end_load->end_angle(c) + (n >= 2 ? 0.5 * BendingTerm::turning_angle(c, n - 1) : 0.0);
    for (int k = 0; k <= n; ++k)
      {
        out.S.push_back(k * lambda0);
        out.x.push_back(c.x[k].x);
        out.y.push_back(c.x[k].y);
      }
    return out;
  }

  std::vector<std::pair<std::string, double>> ChainModel::statistics() const
  {
    if (capstan_loading)
      {
        // The chain's own statics: each frictional node multiplies the
        // compression by (1 + mu tan(zeta/2)) / (1 - mu tan(zeta/2)).
        const auto chain_law = [&](const double mu) {
          const double tau = mu * std::tan(0.5 * cap.zeta);
          return capstan.end_force * std::pow((1.0 + tau) / (1.0 - tau), cap.frictional);
        };
        return {{"frictional_nodes", cap.frictional},
                {"segments", nodes.last - 1},
                {"segment_length", lambda0},
                {"turning_angle", cap.zeta},
                {"chain_dynamic", chain_law(cap.mu_dynamic)},
                {"chain_static", chain_law(cap.mu_static)},
                {"time", t},
                {"time_step", dt}};
      }
    if (!clamped)
      return {};
    return {{"segments", nodes.last - 1},
            {"segment_length", lambda0},
            {"steps", static_cast<double>(steps)},
            {"time", t},
            {"time_step", dt},
            {"damping", drag}};
  }

  void ChainModel::build_capstan(const scene::ChainScene &scene)
  {
    // Nodes on the circle of radius Rc (the centreline on the wall), one
    // chord lambda_0 apart, turning clockwise by zeta at each. The
    // frictional nodes are the free interior ones: 2 .. n-1 under velocity
    // control (nodes 0 and 1 are pushed), 1 .. n-1 under force control; at
    // the end nodes the load acts along the segment.
    capstan = scene.capstan;
    const auto &w = scene.wire;
    const auto &fr = scene.contact.friction;
    const bool velocity = capstan.velocity_control;
    const double k1 = w.axial_stiffness / lambda0;
    const double mass = w.mass_per_length * lambda0;
    const double kn = scene.contact.normal_stiffness * lambda0;
    cap.Rc = radius - 0.5 * diameter;
    cap.mu_static = fr.wall_static_coefficient;
    cap.mu_dynamic = fr.wall_dynamic_coefficient;
    capstan_loading = true;
    stretching_stiffness = k1;
    cap.zeta = 2.0 * std::asin(0.5 * lambda0 / cap.Rc);
    cap.frictional = std::max(1, static_cast<int>(std::lround(capstan.wrap_angle / cap.zeta)));
    const int n = velocity ? cap.frictional + 2 : cap.frictional + 1;
    cap.first_free = velocity ? 2 : 0;
    const double start_angle = 0.5 * M_PI + 0.5 * n * cap.zeta;
    nodes = Chain(n + 1);
    nodes.lambda0 = lambda0;
    nodes.node_mass = mass;
    nodes.first = 0;
    nodes.last = n + 1;
    nodes.n_prescribed = nodes.n_prescribed_last = velocity ? 2 : 0;
    for (int k = 0; k <= n; ++k)
      nodes.x[k] = on_circle(cap.Rc, start_angle - k * cap.zeta);
    cap.x0 = nodes.x;
    cap.roller_r = cap.Rc;

    // The moment that holds an end segment at the wall's curvature: the
    // bending spring next to it turns by -zeta (clockwise).
    const double held = k2 * cap.zeta;
    terms.push_back(std::make_unique<StretchingTerm>(k1, scene.discrete.axial_damping, n + 1));
    auto b = std::make_unique<BendingTerm>(material::MomentCurvatureLaw(k2),
                                           scene.discrete.rotational_damping, n + 1);
    bending = b.get();
    terms.push_back(std::move(b));
    ContactLaw wall;
    wall.diameter = diameter;
    wall.normal_stiffness = kn;
    wall.friction = true;
    wall.coefficients.mu_static = fr.wall_static_coefficient;
    wall.coefficients.mu_dynamic = fr.wall_dynamic_coefficient;
    wall.coefficients.threshold_velocity = fr.threshold_velocity;
    wall.coefficients.tangential_stiffness = fr.tangential_stiffness_ratio * kn;
    wall.surface_torque = fr.surface_torque;
    terms.push_back(std::make_unique<WallContactTerm>(radius, wall, n + 1));
    auto resist = std::make_unique<EndThrustTerm>(EndThrustTerm::End::last, 0.0, -held);
    cap.lead = resist.get();
    terms.push_back(std::move(resist));
    if (!velocity)
      {
        auto p = std::make_unique<EndThrustTerm>(EndThrustTerm::End::first, capstan.end_force, held);
        cap.push = p.get();
        terms.push_back(std::move(p));
      }
    if (scene.discrete.translational_damping > 0.0)
      terms.push_back(std::make_unique<DampingTerm>(scene.discrete.translational_damping, n + 1));
    effects = {"stretching", "bending", "wall contact", "friction", "end loads"};

    dt = stable_time_step(scene.discrete);
  }

  void ChainModel::place_pushed_nodes()
  {
    // Velocity control pushes nodes 0 and 1 along the wall. As a roller
    // (default) they are like a wire in a channel that holds its direction
    // but not its distance from the centre: their polar angles are
    // prescribed and their common radius is free (mass 2 m), so the wall,
    // not the support, carries the pressure next to them. Held, their
    // radius is fixed too, and the support takes the wall pressure, and with
    // it the friction, of a boundary layer of length (EI/k_n)^(1/4).
    const double psi = capstan.pushed(t) / cap.Rc, omega = capstan.push_speed(t) / cap.Rc;
    for (int k = 0; k < 2; ++k)
      {
        const double a = std::atan2(cap.x0[k].y, cap.x0[k].x) - psi;
        nodes.x[k] = on_circle(cap.roller_r, a);
        nodes.v[k] =
            omega * cap.roller_r * Vec2{std::sin(a), -std::cos(a)} + cap.roller_vr * on_circle(1.0, a);
      }
  }

  void ChainModel::capstan_step()
  {
    auto &c = nodes;
    const int n = c.last - 1;
    // The end loads rise over the ramp time (with the speed), so no axial
    // wave is started; under force control the push then keeps rising.
    cap.lead->set_thrust(capstan.end_force_at(t));
    if (capstan.velocity_control)
      place_pushed_nodes();
    else
      cap.push->set_thrust(capstan.push_force_at(t));
    std::fill(c.f.begin(), c.f.end(), Vec2{});
    std::fill(c.contact_force.begin(), c.contact_force.end(), 0.0);
    step_energy = StepEnergy{};
    for (auto &term : terms)
      term->add_forces(c, dt, step_energy);
    if (capstan.velocity_control && capstan.trailing_roller)
      {
        const double radial = dot(c.f[0], on_circle(1.0, std::atan2(c.x[0].y, c.x[0].x))) +
                              dot(c.f[1], on_circle(1.0, std::atan2(c.x[1].y, c.x[1].x)));
        cap.roller_vr += dt * radial / (2.0 * c.node_mass);
        cap.roller_r += dt * cap.roller_vr;
      }
    // Semi-implicit Euler (the injection scenes' scheme) on the free nodes.
    for (int k = cap.first_free; k <= n; ++k)
      {
        c.v[k] += (dt / c.node_mass) * c.f[k];
        c.x[k] += dt * c.v[k];
      }
    for (auto &term : terms)
      term->commit();
    t += dt;
    ++steps;
    if (capstan.velocity_control)
      place_pushed_nodes(); // where the next step's forces will find them
    ledger.stretching = step_energy.stretching;
    ledger.bending = step_energy.bending;
    ledger.contact = step_energy.contact;
    ledger.friction += step_energy.friction_work;
    ledger.damping += step_energy.damping_work;
  }

  core::CapstanState ChainModel::capstan_state() const
  {
    if (!capstan_loading)
      return core::Model::capstan_state();
    const auto &c = nodes;
    const int n = c.last - 1;
    const double k1 = stretching_stiffness;
    const auto compression = [&](const int k) { return k1 * (lambda0 - norm(c.x[k + 1] - c.x[k])); };
    const bool velocity = capstan.velocity_control;
    core::CapstanState s;
    s.wrap_angle = cap.frictional * cap.zeta;
    s.pushed = velocity ? capstan.pushed(t) : 0.0;
    s.push_force = velocity ? compression(1) : capstan.push_force_at(t);
    s.trailing_compression = compression(velocity ? 1 : 0); // where the wire leaves the pushed end
    s.lead_slide = cap.Rc * (std::atan2(cap.x0[n].y, cap.x0[n].x) - std::atan2(c.x[n].y, c.x[n].x));
    s.max_penetration = step_energy.max_penetration;
    // Against the angle from the midpoint of the last segment, where the
    // leading end's load enters the friction.
    for (int k = 0; k < n; ++k)
      s.profile.push_back({{(n - 1 - k) * cap.zeta, compression(k)}});
    return s;
  }
} // namespace wirefem::discrete
