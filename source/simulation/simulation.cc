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

#include <nlohmann/json.hpp>

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

    constexpr std::uint64_t checkpoint_magic = 0x77666d72756e3031ull; // "wfmrun01"
    /// Layout of checkpoint.bin: magic, version, payload size, FNV-1a 64
    /// checksum of the payload, payload (fingerprint, loop state, pvd
    /// entries, the model's state).
    constexpr std::uint64_t checkpoint_version = 4;

    std::uint64_t fnv1a(const std::string &bytes)
    {
      std::uint64_t h = 0xcbf29ce484222325ull;
      for (const unsigned char c : bytes)
        {
          h ^= c;
          h *= 0x100000001b3ull;
        }
      return h;
    }

    /// What the run loop carries from step to step besides the model.
    struct LoopState
    {
      double next_row = 0.0;
      double next_vtu = 0.0;
      int vtu_count = 0;
      std::int32_t padding = 0; // written with the rest: no undefined bytes in the checkpoint
      // Running mean of the inlet force over the jamming window, in injected
      // length: a step that injects dL moves the mean by dL/window.
      double force_mean = 0.0;
      double previous_length = 0.0;
      double max_penetration = 0.0;
      double wall_time = 0.0; // spent before this process (resumed runs)
    };
    static_assert(sizeof(LoopState) == 6 * sizeof(double) + 2 * sizeof(std::int32_t),
                  "LoopState has padding");

    // The first key whose value differs between two scene fingerprints
    // (scene::Scene::fingerprint), for the message that refuses a resume.
    std::string first_difference(const std::string &here, const std::string &there)
    {
      const auto lines = [](const std::string &text) {
        std::map<std::string, std::string> m;
        std::istringstream in(text);
        for (std::string line; std::getline(in, line);)
          if (const auto eq = line.find(" = "); eq != std::string::npos)
            m[line.substr(0, eq)] = line.substr(eq + 3);
        return m;
      };
      const auto a = lines(here), b = lines(there);
      for (const auto &[key, value] : a)
        if (const auto it = b.find(key); it == b.end() || it->second != value)
          return fmt::format("{} is {} here and {} in the checkpoint", key, value,
                             it == b.end() ? std::string("absent") : it->second);
      for (const auto &[key, value] : b)
        if (a.find(key) == a.end())
          return fmt::format("{} is in the checkpoint but not in this scene", key);
      return "different scene parameters";
    }

    void write_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, const LoopState &loop,
                          const io::PvdCollection &pvd, const core::Model &model)
    {
      // Written next to the final name and renamed, so an interruption while
      // writing leaves the previous checkpoint intact.
      const auto tmp = file.string() + ".tmp";
      {
        std::ostringstream out(std::ios::binary);
        const auto &fp = scene.fingerprint;
        core::write_raw(out, static_cast<std::uint64_t>(fp.size()));
        out.write(fp.data(), static_cast<std::streamsize>(fp.size()));
        core::write_raw(out, loop);
        core::write_raw(out, static_cast<std::uint64_t>(pvd.entries().size()));
        for (const auto &[time, name] : pvd.entries())
          {
            core::write_raw(out, time);
            core::write_raw(out, static_cast<std::uint64_t>(name.size()));
            out.write(name.data(), static_cast<std::streamsize>(name.size()));
          }
        model.save(out);
        const std::string payload = out.str();
        std::ofstream file_out(tmp, std::ios::binary);
        core::write_raw(file_out, checkpoint_magic);
        core::write_raw(file_out, checkpoint_version);
        core::write_raw(file_out, static_cast<std::uint64_t>(payload.size()));
        core::write_raw(file_out, fnv1a(payload));
        file_out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
        if (!file_out)
          throw std::runtime_error("cannot write " + tmp);
      }
      std::filesystem::rename(tmp, file);
    }

    void read_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, LoopState &loop,
                         io::PvdCollection &pvd, core::Model &model)
    {
      std::ifstream in(file, std::ios::binary);
      if (!in)
        throw scene::InputError(file.string() + ": no checkpoint to resume from");
      try
        {
          if (core::read_raw<std::uint64_t>(in) != checkpoint_magic)
            throw std::runtime_error("not a wirefem checkpoint");
          if (const auto version = core::read_raw<std::uint64_t>(in); version != checkpoint_version)
            throw std::runtime_error(
                fmt::format("checkpoint version {}, this wirefem reads {}", version, checkpoint_version));
          const auto size = core::read_raw<std::uint64_t>(in);
          const auto checksum = core::read_raw<std::uint64_t>(in);
          const auto at = in.tellg();
          in.seekg(0, std::ios::end);
          const auto available = static_cast<std::uint64_t>(in.tellg() - at);
          in.seekg(at);
          if (size != available)
            throw std::runtime_error(
                fmt::format("damaged: {} bytes of state where {} were written", available, size));
          std::string payload(size, '\0');
          in.read(payload.data(), static_cast<std::streamsize>(size));
          if (!in || fnv1a(payload) != checksum)
            throw std::runtime_error("damaged: its checksum does not match its contents");
          std::istringstream state(payload, std::ios::binary);
          std::string fp(core::read_raw<std::uint64_t>(state), ' ');
          state.read(fp.data(), static_cast<std::streamsize>(fp.size()));
          if (fp != scene.fingerprint)
            throw std::runtime_error("it was written for other scene parameters: " +
                                     first_difference(scene.fingerprint, fp));
          loop = core::read_raw<LoopState>(state);
          const auto n = core::read_raw<std::uint64_t>(state);
          for (std::uint64_t k = 0; k < n; ++k)
            {
              const auto time = core::read_raw<double>(state);
              std::string name(core::read_raw<std::uint64_t>(state), ' ');
              state.read(name.data(), static_cast<std::streamsize>(name.size()));
              pvd.add(time, name);
            }
          model.load(state);
          if (state.peek() != std::char_traits<char>::eof())
            throw std::runtime_error("damaged: state left over after the model");
          if (!model.finite())
            throw std::runtime_error("damaged: the state read back is not finite");
        }
      catch (const std::runtime_error &e)
        {
          throw scene::InputError(file.string() + ": cannot resume: " + e.what());
        }
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
      std::filesystem::create_directories(run.dir);
      std::cout << fmt::format("wirefem {}: scene {} ({} model), f = r/d = {}, {}\n", version(),
                               run.scene.name, model.name(), run.radius(), model.description())
                << "active effects: " << join(model.active_effects()) << '\n'
                << "output: " << run.dir.string() << std::endl;
      if (run.options.resume)
        std::cout << fmt::format("resuming at t = {:.6g}, L = {:.6g}, step {}\n", model.time(),
                                 model.injected_length(), model.n_steps());
      try
        {
          run.series = std::make_unique<io::SeriesWriter>((run.dir / "series.csv").string(), columns,
                                                          run.options.resume ? model.time() : -1.0);
        }
      catch (const io::SeriesColumnsError &e)
        {
          throw scene::InputError(std::string("cannot resume: ") + e.what());
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
                               0.5 * (model.force_left() + model.force_right()),
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
      loop.force_mean += mean_weight * (0.5 * (model.force_left() + model.force_right()) - loop.force_mean);
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
          result.stop_reason =
              fmt::format("contact overlap {:.3f} d exceeds 0.5 d: Contact/Normal stiffness too low for the "
                          "forces, or the time step too large",
                          s.max_penetration);
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
      if (run.scene.output.checkpoint_interval > 0 && model.n_steps() % 1024 == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - run.last_checkpoint).count() >=
              run.scene.output.checkpoint_interval)
        save_checkpoint(run);
      if (model.time() >= inj.maximum_time)
        {
          result.stop_reason = fmt::format("reached Injection/Maximum time {:.4g}", inj.maximum_time);
          return true;
        }
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

    nlohmann::json summary(const Run &run)
    {
      const auto &model = run.model;
      const auto &result = run.result;
      const auto &e = model.energies();
      nlohmann::json j;
      describe_run(j, model, "injection");
      j["scene"] = run.scene.name;
      j["cavity_radius"] = run.radius();
      j["phi_final"] = result.phi_final;
      j["injected_length"] = model.injected_length();
      j["jammed"] = result.jammed;
      j["failed"] = result.failed;
      j["interrupted"] = result.interrupted;
      j["stop_reason"] = result.stop_reason;
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
      j["force_final"] = 0.5 * (model.force_left() + model.force_right());
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
    Run run(scene, options);
    open_run(run);
    step_until_done(run);
    finish_run(run);
    return run.result;
  }
} // namespace wirefem::simulation
