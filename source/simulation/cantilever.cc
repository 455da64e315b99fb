#include <wirefem/simulation/make_model.h>
#include <wirefem/io/atomic_file.h>
#include <wirefem/simulation/cantilever.h>
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
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CantileverResult, converged, tip_x, tip_y, tip_rotation, residual,
                                     wall_time_s)

  namespace
  {
    /// shape.csv (s, x, y per node of the last equilibrium) and history.csv
    /// (one row per recorded equilibrium).
    void write_tables(const std::filesystem::path &dir, const core::Equilibrium &eq,
                      const std::vector<std::array<double, 5>> &recorded)
    {
      std::ofstream shape(dir / "shape.csv");
      shape << "s,x,y\n";
      for (std::size_t k = 0; k < eq.S.size(); ++k)
        shape << fmt::format("{:.17g},{:.17g},{:.17g}\n", eq.S[k], eq.x[k], eq.y[k]);
      std::ofstream history(dir / "history.csv");
      history << "load_factor,tip_x,tip_y,tip_rotation,plastic_work\n";
      for (const auto &h : recorded)
        history << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", h[0], h[1], h[2], h[3], h[4]);
    }
  } // namespace

  CantileverResult run_cantilever(const scene::Scene &scene, const RunOptions &options)
  {
    check_output_place(scene, options);
    const auto wall_start = std::chrono::steady_clock::now();
    const auto &cl = scene.cantilever;
    const bool fem = scene.model == scene::ModelType::fem;
    const std::filesystem::path dir(scene.output.directory);
    std::cout << fmt::format("wirefem: scene {} (cantilever, {} model), L = {}\n", scene.name,
                             fem ? "fem" : "discrete", cl.length)
              << "output: " << dir.string() << std::endl;
    // Both models follow the load history with their own solvers: the chain
    // by dynamic relaxation, the FEM by Newton's method with load increments.
    const auto model = make_model(scene);
    prepare_output_directory(dir, options.replace);
    CantileverResult result;
    std::vector<std::array<double, 5>> recorded; // load factor, tip x, y, rotation, plastic work
    core::Equilibrium eq;
    for (const double target : scene::load_points(cl))
      {
        eq = model->equilibrate(target);
        result.converged = eq.converged;
        if (!eq.converged)
          break;
        recorded.push_back({{target, eq.tip_x, eq.tip_y, eq.tip_rotation, model->energies().plastic}});
      }
    result.residual = eq.residual;
    result.tip_x = eq.tip_x;
    result.tip_y = eq.tip_y;
    result.tip_rotation = eq.tip_rotation;
    result.steps = model->n_steps();
    result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const auto &effects = model->active_effects();
    std::cout << model->description() << "\nactive effects: " << fmt::format("{}", fmt::join(effects, ", "))
              << std::endl;

    write_tables(dir, eq, recorded);
    nlohmann::json j;
    describe_run(j, *model, "cantilever");
    for (const auto &[key, value] : model->statistics())
      j[key] = value;
    j["length"] = cl.length;
    j["end_force"] = {cl.end_force_x, cl.end_force_y};
    j["end_moment"] = cl.end_moment;
    j.update(nlohmann::json(result));
    j["plastic_work"] = recorded.empty() ? 0.0 : recorded.back()[4];
    const auto &ledger = model->energies();
    j["energy"] = {{"bending", ledger.bending}, {"stretching", ledger.stretching}, {"shear", ledger.shear}};
    io::write_file_atomically(dir / "summary.json", j.dump(2) + '\n');

    if (result.converged)
      std::cout << fmt::format("finished: equilibrium (residual {:.2e}) after {} {}, {:.2f} s\n"
                               "tip = ({:.12g}, {:.12g}), tip rotation = {:.12g}\n",
                               result.residual, result.steps, fem ? "load increments" : "steps",
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
