#include <wirefem/analysis/fits.h>
#include <wirefem/analysis/observables.h>
#include <wirefem/io/atomic_file.h>
#include <wirefem/core/binary.h>
#include <wirefem/io/picture.h>
#include <wirefem/io/progress.h>
#include <wirefem/io/series_writer.h>
#include <wirefem/io/vtu_writer.h>
#include <wirefem/scene/scene_reader.h>
#include <wirefem/simulation/make_model.h>
#include <wirefem/simulation/simulation.h>
#include <wirefem/version.h>

#include "run_files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <sstream>
#include <map>
#include <memory>

namespace wirefem::simulation
{
  namespace
  {
    /// A fit's record in summary.json: its values and the window it used, or
    /// why it could not be made.
    template <typename Fit>
    nlohmann::json fit_record(const Fit &fit, nlohmann::json values)
    {
      if (!fit.ok)
        return {{"reason", fit.reason}};
      values["log_prefactor"] = fit.log_prefactor;
      values["phi_min"] = fit.phi_min;
      values["phi_max"] = fit.phi_max;
      values["rows"] = fit.n_points;
      return values;
    }

    /// gamma of N_l ~ phi^gamma and (phi_c, beta) of F ~ (phi_c - phi)^beta
    /// from the run's series (docs/analysis.md, "Fits"); null where a fit is not possible.
    void add_fits(nlohmann::json &j, const std::string &series_file, const double phi_final)
    {
      const auto c = io::read_series_columns(series_file, {"phi", "loops", "force"});
      const auto loops = analysis::fit_loop_exponent(c[0], c[1]);
      const auto force = analysis::fit_jamming_force(c[0], c[2], 0.5 * phi_final);
      j["fits"]["loops"] = fit_record(loops, {{"gamma", loops.gamma}, {"gamma_error", loops.gamma_error}});
      j["fits"]["force"] = fit_record(force, {{"phi_c", force.phi_c},
                                              {"phi_c_error", force.phi_c_error},
                                              {"beta", force.beta},
                                              {"beta_error", force.beta_error}});
      // The exponents again at the top level (null without a fit).
      for (const char *key : {"gamma", "gamma_error"})
        j[key] = loops.ok ? j["fits"]["loops"][key] : nlohmann::json();
      for (const char *key : {"phi_c", "phi_c_error", "beta", "beta_error"})
        j[key] = force.ok ? j["fits"]["force"][key] : nlohmann::json();
    }

    const std::vector<std::string> columns = {"time",
                                              "injected_length",
                                              "phi",
                                              "force",
                                              "force_left",
                                              "force_right",
                                              "loops",
                                              "contacts",
                                              "wall_contacts",
                                              "energy_bending",
                                              "energy_stretching",
                                              "energy_kinetic",
                                              "energy_contact",
                                              "plastic_dissipation",
                                              "friction_dissipation",
                                              "damping_dissipation",
                                              "injection_work",
                                              "energy_balance_error",
                                              "max_penetration",
                                              "symmetry",
                                              "curvature_ratio",
                                              "inner_wire_fraction"};

    // Set by SIGINT/SIGTERM; the loop stops at the end of the current step.
    volatile std::sig_atomic_t interrupt_requested = 0;
    extern "C" void request_interrupt(int)
    {
      interrupt_requested = 1;
    }

    /// Quality alarms (docs/output.md, "Warnings"): a step below this
    /// (time units; the shipped scenes start with steps of 3e-3 to 0.25) makes a run
    /// that may not finish in a useful time; an energy balance error above
    /// the limit at the end makes a result that cannot be trusted.
    constexpr double time_step_floor = 1e-5;
    constexpr double balance_limit = 0.01;

    void warn(RunResult &result, const std::string &text)
    {
      std::cerr << "wirefem: warning: " << text << std::endl;
      result.warnings.push_back(text);
    }

    std::string join(const std::vector<std::string> &v)
    {
      std::string s;
      for (const auto &x : v)
        s += (s.empty() ? "" : ", ") + x;
      return s;
    }
    /// Everything one run works on: the Box2D-style context that the stages
    /// below take in turn (open, step and check, observe, finish).
    struct Run
    {
      Run(const scene::Scene &scene, const RunOptions &options)
        : scene(scene)
        , options(options)
        , wall_start(std::chrono::steady_clock::now())
        , model_ptr(make_model(scene))
        , model(*model_ptr)
        , dir(scene.output.directory)
        , checkpoint_file(dir / "checkpoint.bin")
        , pvd((dir / "wire.pvd").string())
        , progress(scene.output.progress)
      {
      }
      const scene::Scene &scene;
      const RunOptions &options;
      const std::chrono::steady_clock::time_point wall_start;
      const std::unique_ptr<core::Model> model_ptr;
      core::Model &model;
      const std::filesystem::path dir;
      const std::filesystem::path checkpoint_file;
      io::PvdCollection pvd;
      std::unique_ptr<io::SeriesWriter> series;
      io::Progress progress;
      LoopState loop;
      RunResult result;
      unsigned long steps_at_start = 0; ///< rate and ETA count what this process did
      double phi_at_start = 0.0;
      std::chrono::steady_clock::time_point last_checkpoint;

      double radius() const { return scene.cavity.radius; }
      /// How many channels push (Injection/Channel positions: one or two).
      int channels() const { return static_cast<int>(scene.injection.channel_positions.size()); }
      /// The inlet force: the mean over the pushing channels.
      double inlet_force() const
      {
        return channels() == 1 ? model.force_left() : 0.5 * (model.force_left() + model.force_right());
      }
      double elapsed() const
      {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      }
    };

    /// Resumes from the checkpoint if asked, prints the banner and opens
    /// series.csv (continued where the checkpoint left it).
    void open_run(Run &run)
    {
      auto &model = run.model;
      auto &loop = run.loop;
      loop.next_row = loop.next_vtu = loop.previous_length = model.injected_length();
      if (run.options.resume)
        read_checkpoint(run.checkpoint_file, run.scene, loop, run.pvd, model);
      prepare_output_directory(run.dir, run.options.replace);
      std::cout << fmt::format("wirefem {}: scene {} ({} model), f = r/d = {}, {}\n", version(),
                               run.scene.name, model.name(), run.radius(), model.description())
                << "active effects: " << join(model.active_effects()) << '\n'
                << "output: " << run.dir.string() << std::endl;
      if (run.options.resume)
        std::cout << fmt::format("resuming at t = {:.6g}, L = {:.6g}, step {}\n", model.time(),
                                 model.injected_length(), model.n_steps());
      // On resume, a series.csv that is not the checkpoint's is refused
      // (io::SeriesResumeError, bad input) and left as it was.
      run.series = std::make_unique<io::SeriesWriter>((run.dir / "series.csv").string(), columns,
                                                      run.options.resume ? model.time() : -1.0, loop.rows);
      if (const double dt = model.time_step(); dt < time_step_floor)
        {
          const double L_max =
              run.scene.injection.maximum_packing_density * M_PI * run.radius() * run.radius();
          const double steps =
              (L_max - model.injected_length()) / (run.channels() * run.scene.injection.speed * dt);
          warn(run.result,
               fmt::format("time step {:.3g} is below {:g}: about {:.2g} steps to Injection/Maximum "
                           "packing density (the stiffest term sets the step: Contact/Normal "
                           "stiffness, Wire/Axial stiffness or the dashpots)",
                           dt, time_step_floor, steps));
        }
      run.steps_at_start = model.n_steps();
      run.phi_at_start = analysis::packing_density(model.injected_length(), run.radius());
      run.result.max_penetration = loop.max_penetration;
      run.last_checkpoint = std::chrono::steady_clock::now();
    }

    void save_checkpoint(Run &run)
    {
      run.loop.max_penetration = run.result.max_penetration;
      LoopState saved = run.loop;
      saved.wall_time += run.elapsed();
      write_checkpoint(run.checkpoint_file, run.scene, saved, run.pvd, run.model);
      run.last_checkpoint = std::chrono::steady_clock::now();
    }

    /// The wire now: a row of series.csv (write_row), a VTU file when due
    /// (or force_vtu), and the loops and morphology of the result.
    core::WireState observe(Run &run, const bool force_vtu, const bool write_row)
    {
      auto &model = run.model;
      const auto w = model.wire_state();
      const auto morph = analysis::classify(w);
      const int loops = analysis::count_loops(w);
      const auto &e = model.energies();
      const auto s = model.report();
      const double phi = analysis::packing_density(w.injected_length, run.radius());
      if (write_row)
        run.series->write_row({model.time(),
                               w.injected_length,
                               phi,
                               run.inlet_force(),
                               model.force_left(),
                               model.force_right(),
                               double(loops),
                               double(s.n_self_contacts),
                               double(s.n_wall_contacts),
                               e.bending,
                               e.stretching,
                               e.kinetic,
                               e.contact,
                               e.plastic,
                               e.friction,
                               e.damping,
                               e.injection_work,
                               e.balance_error(),
                               s.max_penetration,
                               morph.symmetry,
                               morph.curvature_ratio,
                               morph.inner_wire_fraction});
      if (write_row)
        ++run.loop.rows;
      const double vtu_interval = run.scene.output.vtu_interval;
      if (force_vtu || (vtu_interval > 0 && w.injected_length >= run.loop.next_vtu))
        {
          const std::string name = fmt::format("wire_{:05d}.vtu", run.loop.vtu_count++);
          io::write_vtu((run.dir / name).string(), w);
          run.pvd.add(w.time, name);
          run.pvd.write();
          run.loop.next_vtu += vtu_interval;
        }
      run.result.loops = loops;
      run.result.shape = morph;
      return w;
    }

    /// After a step: the jamming force's running mean, a row when due, and
    /// the reasons to stop (a numerical limit, jamming, the maximum packing
    /// density or time, an interruption). True when the run ends here.
    bool after_step(Run &run)
    {
      auto &model = run.model;
      auto &loop = run.loop;
      auto &result = run.result;
      const auto &inj = run.scene.injection;
      const auto s = model.report();
      result.max_penetration = std::max(result.max_penetration, s.max_penetration);
      const double L = model.injected_length();
      const double mean_weight = std::min(1.0, (L - loop.previous_length) / inj.jamming_window);
      loop.previous_length = L;
      loop.force_mean += mean_weight * (run.inlet_force() - loop.force_mean);
      const double phi = analysis::packing_density(L, run.radius());
      if (L >= loop.next_row)
        {
          observe(run, false, true);
          loop.next_row += run.scene.output.interval;
        }
      if (model.n_steps() % 256 == 0 && !model.finite())
        {
          result.failed = true;
          result.stop_reason = "numerical blow-up: non-finite positions (reduce the time step)";
          return true;
        }
      if (s.max_penetration > 0.5)
        {
          result.failed = true;
          // Which key to look at: a softer contact than the default, or a
          // step too coarse for the contact (or the forces) as they are.
          const double k_n = run.scene.contact.normal_stiffness;
          const double k_default = scene::ContactParameters{}.normal_stiffness;
          result.stop_reason =
              k_n < k_default
                  ? fmt::format(
                        "contact overlap {:.3f} d exceeds 0.5 d: Contact/Normal stiffness {:g} (default "
                        "{:g}) is too low for the forces",
                        s.max_penetration, k_n, k_default)
                  : fmt::format(
                        "contact overlap {:.3f} d exceeds 0.5 d with Contact/Normal stiffness {:g}: the "
                        "time step is too coarse for the contact or the forces too large (lower "
                        "Discrete/Time step factor or FEM/Time step, or Injection/Speed)",
                        s.max_penetration, k_n);
          return true;
        }
      if (loop.force_mean > inj.jamming_force)
        {
          result.jammed = true;
          result.stop_reason = fmt::format("jammed: mean inlet force {:.4g} > Injection/Jamming force {:.4g}",
                                           loop.force_mean, inj.jamming_force);
          return true;
        }
      if (phi >= inj.maximum_packing_density)
        {
          result.stop_reason =
              fmt::format("reached Injection/Maximum packing density {:.4g}", inj.maximum_packing_density);
          return true;
        }
      if (interrupt_requested)
        {
          result.interrupted = true;
          save_checkpoint(run);
          result.stop_reason = "interrupted; continue with --resume";
          return true;
        }
      if (model.time() >= inj.maximum_time)
        {
          result.stop_reason = fmt::format("reached Injection/Maximum time {:.4g}", inj.maximum_time);
          return true;
        }
      // Last: a step that ends the run writes its final row, which a
      // checkpoint taken at that step would not count.
      if (run.scene.output.checkpoint_interval > 0 && model.n_steps() % 1024 == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - run.last_checkpoint).count() >=
              run.scene.output.checkpoint_interval)
        save_checkpoint(run);
      return false;
    }

    void show_progress(Run &run)
    {
      auto &model = run.model;
      const double elapsed = run.elapsed();
      const double phi = analysis::packing_density(model.injected_length(), run.radius());
      const double phi_max = run.scene.injection.maximum_packing_density;
      const double rate = (model.n_steps() - run.steps_at_start) / std::max(elapsed, 1e-9);
      const double eta =
          (phi > run.phi_at_start) ? elapsed * (phi_max - phi) / (phi - run.phi_at_start) : 0.0;
      const auto s = model.report();
      run.progress.update(fmt::format("phi {:.4f}  L {:.1f}  F {:.3g}  contacts {}  {:.0f} steps/s  "
                                      "ETA(phi_max) {:.0f} s",
                                      phi, model.injected_length(), run.loop.force_mean,
                                      s.n_self_contacts + s.n_wall_contacts, rate, eta));
    }

    /// The steps until a reason to stop; SIGINT and SIGTERM end the current
    /// step and leave a checkpoint.
    void step_until_done(Run &run)
    {
      interrupt_requested = 0;
      const auto old_int = std::signal(SIGINT, request_interrupt);
      const auto old_term = std::signal(SIGTERM, request_interrupt);
      while (true)
        {
          try
            {
              run.model.step();
            }
          catch (const std::runtime_error &e)
            {
              run.result.failed = true;
              run.result.stop_reason = e.what();
              break;
            }
          if (after_step(run))
            break;
          if (run.model.n_steps() % 64 == 0)
            show_progress(run);
        }
      run.progress.finish();
      std::signal(SIGINT, old_int);
      std::signal(SIGTERM, old_term);
    }

    /// Any cavity but the paper's circle with its channels: the wall and
    /// the channels (WireState::wall, channels), so that `wirefem analyze`
    /// classifies a run directory by its own cavity.
    void describe_cavity(nlohmann::json &j, const core::WireState &w)
    {
      if (w.wall.empty())
        return;
      auto &c = j["cavity"];
      c["wall"] = nlohmann::json::array();
      for (const auto &p : w.wall)
        c["wall"].push_back({p.x, p.y});
      c["channels"] = nlohmann::json::array();
      for (const auto &ch : w.channels)
        c["channels"].push_back({ch.inlet.x, ch.inlet.y, ch.axis.x, ch.axis.y});
    }

    nlohmann::json summary(const Run &run)
    {
      const auto &model = run.model;
      const auto &result = run.result;
      const auto &e = model.energies();
      nlohmann::json j;
      describe_run(j, model, "injection");
      j["scene"] = run.scene.name;
      j["cavity_radius"] = run.radius();
      describe_cavity(j, model.wire_state());
      j["phi_final"] = result.phi_final;
      j["injected_length"] = model.injected_length();
      j["jammed"] = result.jammed;
      j["failed"] = result.failed;
      j["interrupted"] = result.interrupted;
      j["stop_reason"] = result.stop_reason;
      j["warnings"] = result.warnings;
      j["loops"] = result.loops;
      j["morphology"] = result.shape.phase.empty() ? "plastic" : result.shape.phase;
      for (const auto &[key, value] : analysis::morphology_numbers(result.shape))
        j[key] = value;
      j["steps"] = result.steps;
      j["time"] = model.time();
      j["time_step"] = model.time_step();
      j["wall_time_s"] = result.wall_time_s;
      j["max_penetration"] = result.max_penetration;
      for (const auto &[key, value] : model.statistics())
        j["solver_statistics"][key] = value;
      j["energy"] = {{"initial", e.initial},
                     {"injection_work", e.injection_work},
                     {"stretching", e.stretching},
                     {"shear", e.shear},
                     {"bending", e.bending},
                     {"contact", e.contact},
                     {"kinetic", e.kinetic},
                     {"friction_stored", e.friction_stored},
                     {"plastic_dissipation", e.plastic},
                     {"friction_dissipation", e.friction},
                     {"damping_dissipation", e.damping},
                     {"balance_error", e.balance_error()}};
      j["force_final"] = run.inlet_force();
      add_fits(j, (run.dir / "series.csv").string(), result.phi_final);
      return j;
    }

    /// The final state: its row, VTU and pictures, summary.json, and only
    /// then the checkpoint dropped (a run stopped in between still resumes).
    void finish_run(Run &run)
    {
      auto &model = run.model;
      auto &result = run.result;
      const bool finite = model.finite();
      if (!finite && !result.failed)
        {
          result.failed = true;
          result.stop_reason = "numerical blow-up: non-finite positions";
        }
      // An interrupted run leaves series.csv as the checkpoint has it, so
      // that the resumed run continues it row for row.
      const auto w = finite ? observe(run, true, !result.interrupted) : model.wire_state();
      result.phi_final = analysis::packing_density(model.injected_length(), run.radius());
      result.steps = model.n_steps();
      result.energy_balance_error = model.energies().balance_error();
      result.wall_time_s = run.loop.wall_time + run.elapsed();
      if (!result.interrupted && !(std::abs(result.energy_balance_error) <= balance_limit))
        {
          warn(result,
               fmt::format("energy balance error {:.3g} exceeds {:g}: the energy ledger does not close, "
                           "so the result is not trusted (failed)",
                           result.energy_balance_error, balance_limit));
          result.failed = true;
        }
      if (finite)
        {
          io::PictureOptions opt;
          opt.size_px = run.scene.output.picture_size;
          opt.tangential_channels = run.scene.injection.tangential_channels;
          opt.caption = fmt::format("{}  phi = {:.3f}  loops = {}  {}", run.scene.name, result.phi_final,
                                    result.loops, result.shape.phase);
          io::write_pictures(w, (run.dir / "final.png").string(), (run.dir / "final.svg").string(), opt);
        }
      io::write_file_atomically(run.dir / "summary.json", summary(run).dump(2) + '\n');
      if (!result.interrupted)
        std::filesystem::remove(run.checkpoint_file);
      model.print_timing(std::cout);
      std::cout << fmt::format("{}: {}\nphi = {:.4f}, loops = {}, morphology = {}, symmetry = {:.3f}, "
                               "steps = {}, wall time = {:.1f} s, energy balance error = {:.2e}, "
                               "max overlap = {:.4f} d\n",
                               result.failed ? "stopped" : "finished", result.stop_reason, result.phi_final,
                               result.loops, result.shape.phase, result.shape.symmetry, result.steps,
                               result.wall_time_s, result.energy_balance_error, result.max_penetration);
    }
  } // namespace

  RunResult run(const scene::Scene &scene, const RunOptions &options)
  {
    check_output_place(scene, options);
    Run run(scene, options);
    open_run(run);
    step_until_done(run);
    finish_run(run);
    return run.result;
  }
} // namespace wirefem::simulation
