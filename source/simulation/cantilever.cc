#include <wirefem/discrete/terms.h>
#include <wirefem/fem/cantilever.h>
#include <wirefem/io/atomic_file.h>
#include <wirefem/simulation/cantilever.h>
#include <wirefem/version.h>

#include <fmt/format.h>
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
    /// What either model hands to the output.
    struct Relaxed
    {
      CantileverResult result;
      std::vector<double> S, x, y;
      std::vector<std::string> effects;
      std::string description;
      nlohmann::json extra; ///< model-specific summary fields
      /// Per recorded equilibrium: load factor, tip x, y, rotation, plastic work so far.
      std::vector<std::array<double, 5>> history;
      double bending = 0.0, stretching = 0.0, shear = 0.0;
    };

    Relaxed relax_discrete(const scene::Scene &scene)
    {
      const auto &cl = scene.cantilever;
      const auto &w = scene.wire;
      const double L = cl.length;
      const double l0 = scene.discrete.segment_length;
      const int n = static_cast<int>(std::lround(L / l0));
      const double k1 = w.axial_stiffness / l0;
      const double k2 = w.bending_stiffness / l0;
      const double mass = w.mass_per_length * l0;

      discrete::Chain c(n + 1);
      c.lambda0 = l0;
      c.node_mass = mass;
      c.first = 0;
      c.last = n + 1;
      c.n_prescribed = 1;
      for (int k = 0; k <= n; ++k)
        c.x[k] = {k * l0, 0.0};

      // The same choice of law as the injection scenes (discrete/chain_model.cc).
      const auto &pl = w.plasticity;
      const double alpha = scene.yield_angle();
      const bool plastic = scene.plastic_bending();
      const auto law = plastic ? material::MomentCurvatureLaw(k2, alpha, pl.hardening_slope, pl.hardening)
                               : material::MomentCurvatureLaw(k2);
      const auto clamp_law =
          plastic ? material::MomentCurvatureLaw(2.0 * k2, 0.5 * alpha, pl.hardening_slope, pl.hardening)
                  : material::MomentCurvatureLaw(2.0 * k2);
      std::vector<std::unique_ptr<discrete::Term>> terms;
      terms.push_back(std::make_unique<discrete::StretchingTerm>(k1));
      terms.push_back(std::make_unique<discrete::BendingTerm>(law, 0.0, n + 1));
      terms.push_back(std::make_unique<discrete::ClampTerm>(clamp_law, Vec2{1.0, 0.0}));
      auto end_load =
          std::make_unique<discrete::EndLoadTerm>(Vec2{cl.end_force_x, cl.end_force_y}, cl.end_moment);
      auto *load = end_load.get();
      terms.push_back(std::move(end_load));
      std::vector<std::string> effects{"stretching", "bending"};
      if (plastic)
        effects.push_back("plasticity");
      effects.push_back("end load");

      // Explicit stability as in the injection scenes; the drag is mass
      // proportional, so every mode decays at gamma/2 (the first critically).
      const double omega2 = 4.0 * k1 / mass + 16.0 * k2 / (mass * l0 * l0);
      const double dt = scene.discrete.time_step > 0.0
                            ? scene.discrete.time_step
                            : scene.discrete.time_step_factor * 2.0 / std::sqrt(omega2);
      const double omega1 = 3.5160 * std::sqrt(w.bending_stiffness / (w.mass_per_length * L * L * L * L));
      const double gamma = cl.damping > 0.0 ? cl.damping : 2.0 * omega1;
      const double scale = cl.force_scale(w.bending_stiffness);

      Relaxed out;
      out.description = fmt::format("{} segments, dt = {:.4g}, drag gamma = {:.4g}", n, dt, gamma);
      CantileverResult &result = out.result;
      double t = 0.0;
      discrete::StepEnergy e;
      const double a = 0.5 * gamma * dt;
      // Along the load history: ramp linearly to the next point over
      // Load time / Points per leg, then relax at that load to equilibrium
      // and record it.
      const double ramp = cl.load_time / cl.points_per_leg;
      const auto tip_rotation = [&]() {
        return load->end_angle(c) + (n >= 2 ? 0.5 * discrete::BendingTerm::turning_angle(c, n - 1) : 0.0);
      };
      double factor = 0.0, plastic_work = 0.0;
      for (const double target : scene::load_points(cl))
        {
          const double from = factor, t_leg = t;
          result.converged = false;
          while (true)
            {
              factor = ramp > 0.0 ? from + (target - from) * std::min(1.0, (t - t_leg) / ramp) : target;
              load->set_load_factor(factor);
              std::fill(c.f.begin(), c.f.end(), Vec2{});
              e = discrete::StepEnergy{};
              for (auto &term : terms)
                term->add_forces(c, dt, e);
              double fmax = 0.0;
              for (int k = 1; k <= n; ++k)
                fmax = std::max(fmax, norm(c.f[k]));
              result.residual = fmax / scale;
              if (factor == target && result.residual < cl.tolerance)
                {
                  result.converged = true;
                  break;
                }
              if (t >= cl.maximum_time || !std::isfinite(fmax))
                break;
              // Semi-implicit Euler with the drag taken at the step's midpoint.
              for (int k = 1; k <= n; ++k)
                {
                  c.v[k] = (1.0 / (1.0 + a)) * ((1.0 - a) * c.v[k] + (dt / mass) * c.f[k]);
                  c.x[k] += dt * c.v[k];
                }
              for (auto &term : terms)
                term->commit();
              plastic_work += e.plastic_work;
              t += dt;
              ++result.steps;
            }
          if (!result.converged)
            break;
          out.history.push_back({{factor, c.x[n].x, c.x[n].y, tip_rotation(), plastic_work}});
        }

      result.tip_x = c.x[n].x;
      result.tip_y = c.x[n].y;
      result.tip_rotation = tip_rotation();
      for (int k = 0; k <= n; ++k)
        {
          out.S.push_back(k * l0);
          out.x.push_back(c.x[k].x);
          out.y.push_back(c.x[k].y);
        }
      out.effects = effects;
      out.bending = e.bending;
      out.stretching = e.stretching;
      out.extra = {{"segments", n}, {"segment_length", l0}, {"steps", result.steps},
                   {"time", t},     {"time_step", dt},      {"damping", gamma}};
      return out;
    }

    Relaxed solve_fem(const scene::Scene &scene)
    {
      const auto sol = fem::solve_cantilever(scene);
      Relaxed out;
      out.result.converged = sol.converged;
      out.result.residual = sol.residual;
      out.result.steps = sol.iterations;
      out.result.tip_x = sol.x.back();
      out.result.tip_y = sol.y.back();
      out.result.tip_rotation = sol.theta.back(); // the section angle at the free end
      out.S = sol.S;
      out.x = sol.x;
      out.y = sol.y;
      out.effects = sol.effects;
      out.description = sol.description;
      out.bending = sol.bending;
      out.stretching = sol.stretching;
      out.shear = sol.shear;
      out.history = sol.history;
      out.extra = {
          {"elements", static_cast<long>(std::lround(scene.cantilever.length / scene.fem.element_length))},
          {"element_length", scene.fem.element_length},
          {"degree", scene.fem.degree},
          {"formulation", scene.fem.formulation == scene::Formulation::kirchhoff ? "kirchhoff" : "reissner"},
          {"load_increments", sol.increments},
          {"newton_iterations", sol.iterations},
          {"lowest_eigenvalue", sol.lowest_eigenvalue},
          {"unstable_states_left", sol.unstable_states_left}};
      return out;
    }
  } // namespace

  CantileverResult run_cantilever(const scene::Scene &scene)
  {
    const auto wall_start = std::chrono::steady_clock::now();
    const auto &cl = scene.cantilever;
    const bool fem = scene.model == scene::ModelType::fem;
    const std::filesystem::path dir(scene.output.directory);
    std::filesystem::create_directories(dir);
    std::cout << fmt::format("wirefem: scene {} (cantilever, {} model), L = {}\n", scene.name,
                             fem ? "fem" : "discrete", cl.length)
              << "output: " << dir.string() << std::endl;
    Relaxed r = fem ? solve_fem(scene) : relax_discrete(scene);
    CantileverResult &result = r.result;
    result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    std::cout << r.description << "\nactive effects: ";
    for (std::size_t i = 0; i < r.effects.size(); ++i)
      std::cout << (i ? ", " : "") << r.effects[i];
    std::cout << std::endl;

    {
      std::ofstream shape(dir / "shape.csv");
      shape << "s,x,y\n";
      for (std::size_t k = 0; k < r.S.size(); ++k)
        shape << fmt::format("{:.17g},{:.17g},{:.17g}\n", r.S[k], r.x[k], r.y[k]);
    }
    {
      std::ofstream history(dir / "history.csv");
      history << "load_factor,tip_x,tip_y,tip_rotation,plastic_work\n";
      for (const auto &h : r.history)
        history << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", h[0], h[1], h[2], h[3], h[4]);
    }
    nlohmann::json j = r.extra;
    j["setup"] = "cantilever";
    j["model"] = fem ? "fem" : "discrete";
    j["length"] = cl.length;
    j["end_force"] = {cl.end_force_x, cl.end_force_y};
    j["end_moment"] = cl.end_moment;
    j["tip_x"] = result.tip_x;
    j["tip_y"] = result.tip_y;
    j["tip_rotation"] = result.tip_rotation;
    j["residual"] = result.residual;
    j["converged"] = result.converged;
    j["wall_time_s"] = result.wall_time_s;
    j["active_effects"] = r.effects;
    j["version"] = version();
    j["plastic_work"] = r.history.empty() ? 0.0 : r.history.back()[4];
    j["energy"] = {{"bending", r.bending}, {"stretching", r.stretching}, {"shear", r.shear}};
    io::write_file_atomically(dir / "summary.json", j.dump(2) + '\n');

    if (result.converged)
      std::cout << fmt::format("finished: equilibrium (residual {:.2e}) after {} {}, {:.2f} s\n"
                               "tip = ({:.12g}, {:.12g}), tip rotation = {:.12g}\n",
                               result.residual, result.steps, fem ? "Newton iterations" : "steps",
                               result.wall_time_s, result.tip_x, result.tip_y, result.tip_rotation);
    else if (fem)
      std::cerr << fmt::format(
          "wirefem: error: Newton did not reach Cantilever/Tolerance = {:g} even with the "
          "load increment halved 12 times: residual {:.3e}\n",
          cl.tolerance, result.residual);
    else
      std::cerr << fmt::format("wirefem: error: no equilibrium by Cantilever/Maximum time = {:g}: residual "
                               "{:.3e} > Cantilever/Tolerance = {:g}{}\n",
                               cl.maximum_time, result.residual, cl.tolerance,
                               std::isfinite(result.residual) ? "" : " (not finite)");
    return result;
  }
} // namespace wirefem::simulation
