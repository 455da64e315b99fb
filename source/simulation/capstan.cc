#include <wirefem/simulation/make_model.h>
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
  namespace
  {
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
  } // namespace

  CapstanResult run_capstan(const scene::Scene &scene)
  {
    const auto wall_start = std::chrono::steady_clock::now();
    const auto &cs = scene.capstan;
    const auto &fr = scene.contact.friction;
    const bool velocity = cs.velocity_control;
    // Both models take the capstan loading and step it with their own
    // integrators: the chain explicitly, the FEM by quasi-static Newton steps.
    const auto model = make_model(scene);
    const std::filesystem::path dir(scene.output.directory);
    std::filesystem::create_directories(dir);
    core::CapstanState state = model->capstan_state();
    std::cout << fmt::format("wirefem: scene {} (capstan, {} model), r = {}, wrap angle {:.6f} rad, mu_st = {}, "
                             "mu_d = {}, {} control\n{}\nactive effects: {}\noutput: {}",
                             scene.name, model->name(), scene.cavity.radius, state.wrap_angle,
                             fr.wall_static_coefficient, fr.wall_dynamic_coefficient,
                             velocity ? "velocity" : "force", model->description(),
                             fmt::join(model->active_effects(), ", "), dir.string())
              << std::endl;

    CapstanResult result;
    result.wrap_angle = state.wrap_angle;
    const double t_end = velocity ? cs.slide_time() : cs.maximum_time;
    const double t_average = 0.5 * (cs.ramp_time + t_end);
    std::ofstream series(dir / "series.csv");
    series << series_header;
    const double output_interval = velocity ? 0.5 : 1.0;
    double next_output = 0.0, force_sum = 0.0, force_time = 0.0, peak = 0.0, penetration = 0.0;
    double last_push = 0.0;
    bool slipped = false, onset_without_equilibrium = false;
    std::string failure;
    std::vector<double> profile_sum(state.profile.size(), 0.0);
    while (true)
      {
        const double t = model->time();
        const double p = state.push_force;
        if (!std::isfinite(p))
          {
            failure = "the push force is not finite";
            break;
          }
        peak = std::max(peak, p);
        penetration = std::max(penetration, state.max_penetration);
        if (t >= next_output)
          {
            series << fmt::format("{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", t, state.pushed, state.lead_slide,
                                  p, state.trailing_compression);
            next_output += output_interval;
          }
        if (velocity && t >= t_end * (1.0 - 1e-12))
          {
            result.finished = true;
            break;
          }
        if (!velocity && state.lead_slide >= cs.slip_distance)
          {
            result.onset_force = p;
            result.finished = slipped = true;
            break;
          }
        if (t > cs.maximum_time)
          break;
        try
          {
            model->step();
          }
        catch (const std::runtime_error &e)
          {
            // Force control: no equilibrium at a larger push, so the wire
            // slips at the last push that had one.
            if (!velocity && model->n_steps() > 0 && t > cs.ramp_time)
              {
                result.finished = slipped = onset_without_equilibrium = true;
                result.onset_force = last_push;
              }
            else
              failure = e.what();
            break;
          }
        last_push = p;
        // The push force and the profile averaged over the second half of
        // the slide (each state held over the step that follows it).
        const double step = model->time() - t;
        if (velocity && t >= t_average)
          {
            force_sum += p * step;
            force_time += step;
            for (std::size_t k = 0; k < profile_sum.size(); ++k)
              profile_sum[k] += state.profile[k][1] * step;
          }
        state = model->capstan_state();
      }
    if (velocity && force_time > 0.0)
      result.push_force = force_sum / force_time;
    else if (velocity)
      result.finished = false;
    result.steps = model->n_steps();
    result.segments = static_cast<int>(state.profile.size());
    result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    // Compression along the wire: velocity control averaged like the push
    // force, force control at the slip.
    auto rows = state.profile;
    if (velocity && force_time > 0.0)
      for (std::size_t k = 0; k < rows.size(); ++k)
        rows[k][1] = profile_sum[k] / force_time;
    write_profile(dir, rows);

    auto j = summary(model->name().c_str(), result, scene, model->active_effects());
    j["solver"] = solver_name(*model);
    j["description"] = model->description();
    for (const auto &[key, value] : model->statistics())
      j[key] = value;
    j["push_force_peak"] = peak;
    j["max_penetration"] = penetration;
    j["time"] = model->time();
    if (!velocity)
      {
        j["onset_force"] = result.onset_force;
        j["onset_without_equilibrium"] = onset_without_equilibrium;
      }
    if (!failure.empty())
      j["failure"] = failure;
    io::write_file_atomically(dir / "summary.json", j.dump(2) + '\n');
    if (!failure.empty())
      std::cerr << fmt::format("wirefem: error: the capstan run failed at t = {:g}: {}\n", model->time(), failure);
    else
      report(result, j, cs, slipped);
    return result;
  }
} // namespace wirefem::simulation
