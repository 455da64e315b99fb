#include <wirefem/simulation/make_model.h>
#include <wirefem/io/atomic_file.h>
#include <wirefem/simulation/capstan.h>
#include <wirefem/version.h>

#include "run_files.h"

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
  // The result's fields in summary.json, named as the members.
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CapstanResult, finished, wrap_angle, push_force, steps, wall_time_s)

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
    nlohmann::json summary(const core::Model &model, const CapstanResult &result, const scene::Scene &scene)
    {
      const auto &cs = scene.capstan;
      const auto &fr = scene.contact.friction;
      nlohmann::json j;
      describe_run(j, model, "capstan");
      j["control"] = cs.velocity_control ? "velocity" : "force";
      j.update(nlohmann::json(result));
      j["end_force"] = cs.end_force;
      j["mu_static"] = fr.wall_static_coefficient;
      j["mu_dynamic"] = fr.wall_dynamic_coefficient;
      j["capstan_dynamic"] = cs.end_force * std::exp(fr.wall_dynamic_coefficient * result.wrap_angle);
      j["capstan_static"] = cs.end_force * std::exp(fr.wall_static_coefficient * result.wrap_angle);
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
    /// One capstan run: the plain context of the stages below.
    struct CapstanRun
    {
      explicit CapstanRun(const scene::Scene &scene)
        : scene(scene)
        , model(make_model(scene))
        , dir(scene.output.directory)
        , wall_start(std::chrono::steady_clock::now())
      {
      }
      const scene::Scene &scene;
      std::unique_ptr<core::Model> model;
      std::filesystem::path dir;
      std::chrono::steady_clock::time_point wall_start;
      core::CapstanState state;
      std::ofstream series;
      CapstanResult result;
      double t_end = 0.0, t_average = 0.0, output_interval = 0.0;
      double next_output = 0.0, force_sum = 0.0, force_time = 0.0, peak = 0.0, penetration = 0.0;
      double last_push = 0.0;
      bool slipped = false, onset_without_equilibrium = false;
      std::string failure;
      std::vector<double> profile_sum;

      bool velocity() const { return scene.capstan.velocity_control; }
    };

    /// The state at the current time: its row of series.csv when due, and
    /// whether the run ends here (the slide done, the wire slipped, a
    /// non-finite force, the maximum time).
    bool record_and_check(CapstanRun &run)
    {
      const auto &cs = run.scene.capstan;
      const auto &state = run.state;
      const double t = run.model->time();
      const double p = state.push_force;
      if (!std::isfinite(p))
        {
          run.failure = "the push force is not finite";
          return true;
        }
      run.peak = std::max(run.peak, p);
      run.penetration = std::max(run.penetration, state.max_penetration);
      if (t >= run.next_output)
        {
          run.series << fmt::format("{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", t, state.pushed,
                                    state.lead_slide, p, state.trailing_compression);
          run.next_output += run.output_interval;
        }
      if (run.velocity() && t >= run.t_end * (1.0 - 1e-12))
        {
          run.result.finished = true;
          return true;
        }
      if (!run.velocity() && state.lead_slide >= cs.slip_distance)
        {
          run.result.onset_force = p;
          run.result.finished = run.slipped = true;
          return true;
        }
      return t > cs.maximum_time;
    }

    /// One step of the model; the push force and the profile averaged over
    /// the second half of the slide (each state held over the step that
    /// follows it). False when the model could not step.
    bool advance(CapstanRun &run)
    {
      const double t = run.model->time();
      const double p = run.state.push_force;
      try
        {
          run.model->step();
        }
      catch (const std::runtime_error &e)
        {
          // Force control: no equilibrium at a larger push, so the wire
          // slips at the last push that had one.
          if (!run.velocity() && run.model->n_steps() > 0 && t > run.scene.capstan.ramp_time)
            {
              run.result.finished = run.slipped = run.onset_without_equilibrium = true;
              run.result.onset_force = run.last_push;
            }
          else
            run.failure = e.what();
          return false;
        }
      run.last_push = p;
      const double step = run.model->time() - t;
      if (run.velocity() && t >= run.t_average)
        {
          run.force_sum += p * step;
          run.force_time += step;
          for (std::size_t k = 0; k < run.profile_sum.size(); ++k)
            run.profile_sum[k] += run.state.profile[k][1] * step;
        }
      run.state = run.model->capstan_state();
      return true;
    }

    /// profile.csv and summary.json, and the closing message.
    void finish_capstan(CapstanRun &run)
    {
      auto &result = run.result;
      auto &model = *run.model;
      const bool averaged = run.velocity() && run.force_time > 0.0;
      if (averaged)
        result.push_force = run.force_sum / run.force_time;
      else if (run.velocity())
        result.finished = false;
      result.steps = model.n_steps();
      result.segments = static_cast<int>(run.state.profile.size());
      result.wall_time_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - run.wall_start).count();
      // Compression along the wire: velocity control averaged like the push
      // force, force control at the slip.
      auto rows = run.state.profile;
      if (averaged)
        for (std::size_t k = 0; k < rows.size(); ++k)
          rows[k][1] = run.profile_sum[k] / run.force_time;
      write_profile(run.dir, rows);

      auto j = summary(model, result, run.scene);
      j["description"] = model.description();
      for (const auto &[key, value] : model.statistics())
        j[key] = value;
      j["push_force_peak"] = run.peak;
      j["max_penetration"] = run.penetration;
      j["time"] = model.time();
      if (!run.velocity())
        {
          j["onset_force"] = result.onset_force;
          j["onset_without_equilibrium"] = run.onset_without_equilibrium;
        }
      if (!run.failure.empty())
        j["failure"] = run.failure;
      io::write_file_atomically(run.dir / "summary.json", j.dump(2) + '\n');
      if (!run.failure.empty())
        std::cerr << fmt::format("wirefem: error: the capstan run failed at t = {:g}: {}\n", model.time(),
                                 run.failure);
      else
        report(result, j, run.scene.capstan, run.slipped);
    }
  } // namespace

  CapstanResult run_capstan(const scene::Scene &scene, const RunOptions &options)
  {
    check_output_place(scene, options);
    const auto &cs = scene.capstan;
    const auto &fr = scene.contact.friction;
    // Both models take the capstan loading and step it with their own
    // integrators: the chain explicitly, the FEM by quasi-static Newton steps.
    CapstanRun run(scene);
    prepare_output_directory(run.dir, options.replace);
    run.state = run.model->capstan_state();
    std::cout << fmt::format(
                     "wirefem: scene {} (capstan, {} model), r = {}, wrap angle {:.6f} rad, mu_st = {}, "
                     "mu_d = {}, {} control\n{}\nactive effects: {}\noutput: {}",
                     scene.name, run.model->name(), scene.cavity.radius, run.state.wrap_angle,
                     fr.wall_static_coefficient, fr.wall_dynamic_coefficient,
                     run.velocity() ? "velocity" : "force", run.model->description(),
                     fmt::join(run.model->active_effects(), ", "), run.dir.string())
              << std::endl;
    run.result.wrap_angle = run.state.wrap_angle;
    run.t_end = run.velocity() ? cs.slide_time() : cs.maximum_time;
    run.t_average = 0.5 * (cs.ramp_time + run.t_end);
    run.output_interval = run.velocity() ? 0.5 : 1.0;
    run.profile_sum.assign(run.state.profile.size(), 0.0);
    run.series.open(run.dir / "series.csv");
    run.series << series_header;
    while (!record_and_check(run) && advance(run))
      ;
    finish_capstan(run);
    return run.result;
  }
} // namespace wirefem::simulation
