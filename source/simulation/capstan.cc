#include <wirefem/discrete/terms.h>
#include <wirefem/fem/capstan.h>
#include <wirefem/io/atomic_file.h>
#include <wirefem/simulation/capstan.h>
#include <wirefem/version.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

namespace wirefem::simulation
{
  using core::Vec2;

  namespace
  {
    Vec2 on_circle(const double radius, const double angle)
    {
      return {radius * std::cos(angle), radius * std::sin(angle)};
    }

    constexpr const char *series_header = "time,pushed,lead_slide,push_force,trailing_compression\n";

    /// Compression along the wire: (angle from the leading end, compression).
    void write_profile(const std::filesystem::path &dir, const std::vector<std::array<double, 2>> &rows)
    {
      std::ofstream profile(dir / "profile.csv");
      profile << "segment,angle,compression\n";
      for (std::size_t k = 0; k < rows.size(); ++k)
        profile << fmt::format("{},{:.17g},{:.17g}\n", k, rows[k][0], rows[k][1]);
    }

    /// What the summaries of both models share: the set-up, the result and
    /// the capstan laws over the run's wrap angle.
    nlohmann::json summary(const char *model, const CapstanResult &result, const scene::Scene &scene,
                           const std::vector<std::string> &effects)
    {
      const auto &cs = scene.capstan;
      const auto &fr = scene.contact.friction;
      nlohmann::json j;
      j["setup"] = "capstan";
      j["model"] = model;
      j["control"] = cs.velocity_control ? "velocity" : "force";
      j["finished"] = result.finished;
      j["wrap_angle"] = result.wrap_angle;
      j["end_force"] = cs.end_force;
      j["mu_static"] = fr.wall_static_coefficient;
      j["mu_dynamic"] = fr.wall_dynamic_coefficient;
      j["push_force"] = result.push_force;
      j["capstan_dynamic"] = cs.end_force * std::exp(fr.wall_dynamic_coefficient * result.wrap_angle);
      j["capstan_static"] = cs.end_force * std::exp(fr.wall_static_coefficient * result.wrap_angle);
      j["steps"] = result.steps;
      j["wall_time_s"] = result.wall_time_s;
      j["active_effects"] = effects;
      j["version"] = version();
      return j;
    }

    void report(const CapstanResult &result, const nlohmann::json &j, const scene::CapstanParameters &cs,
                const bool slipped)
    {
      if (!result.finished)
        std::cerr << fmt::format(
            "wirefem: error: the capstan run did not end by Capstan/Maximum time = {:g}{}\n", cs.maximum_time,
            slipped ? "" : " (the wire never slipped)");
      else if (cs.velocity_control)
        std::cout << fmt::format(
            "finished: pushed {:g} d; push force {:.10g} (capstan law T0 exp(mu_d angle) = "
            "{:.10g}), {} steps, {:.2f} s\n",
            cs.slide, result.push_force, j["capstan_dynamic"].get<double>(), result.steps,
            result.wall_time_s);
      else
        std::cout << fmt::format("finished: slipped at push force {:.10g} (capstan law T0 exp(mu_st angle) = "
                                 "{:.10g}), {} steps, {:.2f} s\n",
                                 result.onset_force, j["capstan_static"].get<double>(), result.steps,
                                 result.wall_time_s);
    }

    /// The rod FEM's capstan (fem/capstan.h), quasi-static.
    CapstanResult run_capstan_fem(const scene::Scene &scene)
    {
      const auto wall_start = std::chrono::steady_clock::now();
      const auto &cs = scene.capstan;
      const auto &fr = scene.contact.friction;
      const std::filesystem::path dir(scene.output.directory);
      std::filesystem::create_directories(dir);
      const std::vector<std::string> effects{"stretching",   "shear",    "bending",
                                             "wall contact", "friction", "end loads"};
      std::cout << fmt::format(
                       "wirefem: scene {} (capstan, rod FEM, quasi-static), r = {}, mu_st = {}, mu_d = "
                       "{}, {} control, {} friction\nactive effects: {}\noutput: {}",
                       scene.name, scene.cavity.radius, fr.wall_static_coefficient,
                       fr.wall_dynamic_coefficient, cs.velocity_control ? "velocity" : "force",
                       scene.fem.spring_friction ? "spring-law" : "regularised", fmt::join(effects, ", "),
                       dir.string())
                << std::endl;
      const auto sol = fem::solve_capstan(scene);
      CapstanResult result;
      result.finished = sol.finished;
      result.wrap_angle = sol.wrap_angle;
      result.segments = static_cast<int>(sol.elements);
      result.push_force = sol.push_force;
      result.onset_force = sol.onset_force;
      result.steps = sol.steps;
      result.wall_time_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      {
        std::ofstream series(dir / "series.csv");
        series << series_header;
        for (const auto &r : sol.series)
          series << fmt::format("{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", r[0], r[1], r[2], r[3], r[4]);
      }
      write_profile(dir, sol.profile);
      auto j = summary("fem", result, scene, effects);
      j["description"] = sol.description;
      j["elements"] = sol.elements;
      j["degree"] = scene.fem.degree;
      j["element_length"] = scene.fem.element_length;
      j["sliding_coefficient"] = sol.sliding_coefficient;
      j["push_force_peak"] = sol.push_force_peak;
      j["capstan_sliding"] = cs.end_force * std::exp(sol.sliding_coefficient * result.wrap_angle);
      j["max_penetration"] = sol.max_penetration;
      j["time"] = sol.time;
      j["time_step"] = sol.time_step;
      j["newton_iterations"] = sol.newton_iterations;
      j["step_cuts"] = sol.step_cuts;
      j["friction_law"] = scene.fem.spring_friction ? "spring" : "regularised";
      if (!cs.velocity_control)
        {
          j["onset_force"] = sol.onset_force;
          j["onset_without_equilibrium"] = sol.onset_without_equilibrium;
        }
      io::write_file_atomically(dir / "summary.json", j.dump(2) + '\n');
      if (!result.finished && cs.velocity_control)
        std::cerr << fmt::format(
            "wirefem: error: the capstan run failed at t = {:g} (Newton did not converge "
            "down to FEM/Minimum time step)\n",
            sol.time);
      else
        report(result, j, cs, false);
      return result;
    }
  } // namespace

  CapstanResult run_capstan(const scene::Scene &scene)
  {
    if (scene.model == scene::ModelType::fem)
      return run_capstan_fem(scene);
    const auto wall_start = std::chrono::steady_clock::now();
    const auto &cs = scene.capstan;
    const auto &w = scene.wire;
    const auto &fr = scene.contact.friction;
    const bool velocity = cs.velocity_control;
    const double diameter = 1.0;
    const double l0 = scene.discrete.segment_length;
    const double Rc = scene.cavity.radius - 0.5 * diameter; // centreline on the wall
    const double k1 = w.axial_stiffness / l0;
    const double k2 = w.bending_stiffness / l0;
    const double mass = w.mass_per_length * l0;
    const double kn = scene.contact.normal_stiffness * l0;

    // Nodes on the circle of radius Rc, one chord lambda_0 apart, turning
    // clockwise by zeta at each. The frictional nodes are the free interior
    // ones: 2 .. n-1 under velocity control (nodes 0 and 1 are pushed), 1 .. n-1
    // under force control; at the end nodes the load acts along the segment.
    const double zeta = 2.0 * std::asin(0.5 * l0 / Rc);
    const int m = std::max(1, static_cast<int>(std::lround(cs.wrap_angle / zeta)));
    const int n = velocity ? m + 2 : m + 1;
    const int first_free = velocity ? 2 : 0;
    CapstanResult result;
    result.wrap_angle = m * zeta;
    result.segments = n;
    const double start_angle = 0.5 * M_PI + 0.5 * n * zeta;

    discrete::Chain c(n + 1);
    c.lambda0 = l0;
    c.node_mass = mass;
    c.first = 0;
    c.last = n + 1;
    c.n_prescribed = velocity ? 2 : 0;
    for (int k = 0; k <= n; ++k)
      c.x[k] = on_circle(Rc, start_angle - k * zeta);
    const std::vector<Vec2> x0 = c.x;

    // The moment that holds an end segment at the wall's curvature: the
    // bending spring next to it turns by -zeta (clockwise).
    const double held = k2 * zeta;
    std::vector<std::unique_ptr<discrete::Term>> terms;
    terms.push_back(std::make_unique<discrete::StretchingTerm>(k1, scene.discrete.axial_damping, n + 1));
    terms.push_back(std::make_unique<discrete::BendingTerm>(material::MomentCurvatureLaw(k2),
                                                            scene.discrete.rotational_damping, n + 1));
    discrete::ContactLaw wall;
    wall.diameter = diameter;
    wall.normal_stiffness = kn;
    wall.friction = true;
    wall.coefficients.mu_static = fr.wall_static_coefficient;
    wall.coefficients.mu_dynamic = fr.wall_dynamic_coefficient;
    wall.coefficients.threshold_velocity = fr.threshold_velocity;
    wall.coefficients.tangential_stiffness = fr.tangential_stiffness_ratio * kn;
    wall.surface_torque = fr.surface_torque;
    terms.push_back(std::make_unique<discrete::WallContactTerm>(scene.cavity.radius, wall, n + 1));
    auto resist = std::make_unique<discrete::EndThrustTerm>(discrete::EndThrustTerm::End::last, 0.0, -held);
    discrete::EndThrustTerm *lead = resist.get();
    terms.push_back(std::move(resist));
    discrete::EndThrustTerm *push = nullptr;
    if (!velocity)
      {
        auto p = std::make_unique<discrete::EndThrustTerm>(discrete::EndThrustTerm::End::first, cs.end_force,
                                                           held);
        push = p.get();
        terms.push_back(std::move(p));
      }
    if (scene.discrete.translational_damping > 0.0)
      terms.push_back(std::make_unique<discrete::DampingTerm>(scene.discrete.translational_damping, n + 1));
    const std::vector<std::string> effects{"stretching", "bending", "wall contact", "friction", "end loads"};

    const double omega2 = 4.0 * k1 / mass + 16.0 * k2 / (mass * l0 * l0) +
                          (4.0 + 4.0 * fr.tangential_stiffness_ratio) * kn / mass;
    const auto &dd = scene.discrete;
    const double dt = dd.time_step > 0.0
                          ? dd.time_step
                          : discrete::explicit_time_step(dd.time_step_factor, omega2,
                                                         discrete::dashpot_rate(mass, l0, dd.axial_damping,
                                                                                dd.rotational_damping,
                                                                                dd.translational_damping));

    const std::filesystem::path dir(scene.output.directory);
    std::filesystem::create_directories(dir);
    std::cout << fmt::format("wirefem: scene {} (capstan, discrete model), r = {}, wrap angle {:.6f} rad "
                             "({} frictional nodes of {} segments), mu_st = {}, mu_d = {}, {} control\n",
                             scene.name, scene.cavity.radius, result.wrap_angle, m, n,
                             fr.wall_static_coefficient, fr.wall_dynamic_coefficient,
                             velocity ? "velocity" : "force")
              << fmt::format("dt = {:.4g}\nactive effects: {}\noutput: {}", dt, fmt::join(effects, ", "),
                             dir.string())
              << std::endl;

    const double t_end = velocity ? cs.slide_time() : cs.maximum_time;
    // Arc distance the leading end moved (clockwise positive).
    const auto lead_slide = [&]() {
      return Rc * (std::atan2(x0[n].y, x0[n].x) - std::atan2(c.x[n].y, c.x[n].x));
    };
    const auto compression = [&](const int k) { return k1 * (l0 - norm(c.x[k + 1] - c.x[k])); };
    const int measured = velocity ? 1 : 0; // the segment where the wire leaves the pushed end

    // Velocity control pushes nodes 0 and 1 along the wall. As a roller
    // (default) they are like a wire in a channel that holds its direction
    // but not its distance from the centre: their polar angles are
    // prescribed and their common radius is free (mass 2 m), so the wall,
    // not the support, carries the pressure next to them. Clamped, their
    // radius is held too, and the support takes the wall pressure, and with
    // it the friction, of a boundary layer of length (EI/k_n)^(1/4): -0.41%
    // of push force at lambda_0 = 0.25 against -0.23% as a roller. Clamped,
    // every node sits on the circle and the chain's statics is exact.
    double roller_r = Rc, roller_vr = 0.0;
    std::ofstream series(dir / "series.csv");
    series << series_header;
    const double output_interval = velocity ? 0.5 : 1.0;
    double next_output = 0.0, t = 0.0, force_sum = 0.0, force_time = 0.0, peak = 0.0;
    discrete::StepEnergy e;
    bool slipped = false;
    std::vector<double> profile_sum(n, 0.0);
    while (t <= cs.maximum_time)
      {
        // The end loads rise over the ramp time (with the speed), so no axial
        // wave is started; under force control the push then keeps rising.
        const double ramp = t < cs.ramp_time ? t / cs.ramp_time : 1.0;
        lead->set_thrust(cs.end_force * ramp);
        if (velocity)
          {
            const double psi = cs.pushed(t) / Rc, omega = cs.push_speed(t) / Rc;
            for (int k = 0; k < 2; ++k)
              {
                const double a = std::atan2(x0[k].y, x0[k].x) - psi;
                c.x[k] = on_circle(roller_r, a);
                c.v[k] = omega * roller_r * Vec2{std::sin(a), -std::cos(a)} + roller_vr * on_circle(1.0, a);
              }
          }
        else
          push->set_thrust(cs.end_force * (ramp + cs.force_rate * std::max(0.0, t - cs.ramp_time)));
        std::fill(c.f.begin(), c.f.end(), Vec2{});
        std::fill(c.contact_force.begin(), c.contact_force.end(), 0.0);
        e = discrete::StepEnergy{};
        for (auto &term : terms)
          term->add_forces(c, dt, e);
        const double p = velocity ? compression(measured) : push->get_thrust();
        if (!std::isfinite(p))
          break;
        peak = std::max(peak, compression(measured));
        if (velocity && t >= 0.5 * (cs.ramp_time + t_end))
          {
            force_sum += p * dt;
            force_time += dt;
            for (int k = 0; k < n; ++k)
              profile_sum[k] += compression(k) * dt;
          }
        if (t >= next_output)
          {
            series << fmt::format("{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", t,
                                  velocity ? cs.pushed(t) : 0.0, lead_slide(), p, compression(measured));
            next_output += output_interval;
          }
        if (velocity && t >= t_end)
          {
            result.finished = true;
            break;
          }
        if (!velocity && lead_slide() >= cs.slip_distance)
          {
            result.onset_force = p;
            result.finished = slipped = true;
            break;
          }
        if (velocity && cs.trailing_roller)
          {
            const double radial = dot(c.f[0], on_circle(1.0, std::atan2(c.x[0].y, c.x[0].x))) +
                                  dot(c.f[1], on_circle(1.0, std::atan2(c.x[1].y, c.x[1].x)));
            roller_vr += dt * radial / (2.0 * mass);
            roller_r += dt * roller_vr;
          }
        // Semi-implicit Euler (the injection scenes' scheme) on the free nodes.
        for (int k = first_free; k <= n; ++k)
          {
            c.v[k] += (dt / mass) * c.f[k];
            c.x[k] += dt * c.v[k];
          }
        for (auto &term : terms)
          term->commit();
        t += dt;
        ++result.steps;
      }
    if (velocity && force_time > 0.0)
      result.push_force = force_sum / force_time;
    result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    {
      // Compression along the wire (velocity control: averaged over the time
      // the push force is; force control: at the slip), against the angle
      // from the midpoint of the last segment, where the leading end's load
      // enters the friction.
      std::vector<std::array<double, 2>> rows(n);
      for (int k = 0; k < n; ++k)
        rows[k] = {{(n - 1 - k) * zeta,
                    velocity && force_time > 0.0 ? profile_sum[k] / force_time : compression(k)}};
      write_profile(dir, rows);
    }

    // References: the continuum capstan law over the wrap angle, and the
    // chain's own statics (each frictional node multiplies the compression
    // by (1 + mu tan(zeta/2)) / (1 - mu tan(zeta/2))).
    const auto chain_law = [&](const double mu) {
      return cs.end_force *
             std::pow((1.0 + mu * std::tan(0.5 * zeta)) / (1.0 - mu * std::tan(0.5 * zeta)), m);
    };
    auto j = summary("discrete", result, scene, effects);
    j["frictional_nodes"] = m;
    j["segments"] = n;
    j["segment_length"] = l0;
    j["turning_angle"] = zeta;
    j["push_force_peak"] = peak;
    j["onset_force"] = result.onset_force;
    j["chain_dynamic"] = chain_law(fr.wall_dynamic_coefficient);
    j["chain_static"] = chain_law(fr.wall_static_coefficient);
    j["max_penetration"] = e.max_penetration;
    j["time"] = t;
    j["time_step"] = dt;
    io::write_file_atomically(dir / "summary.json", j.dump(2) + '\n');
    report(result, j, cs, slipped);
    return result;
  }
} // namespace wirefem::simulation
