#include <wirefem/analysis/fits.h>
#include <wirefem/io/picture.h>
#include <wirefem/io/series_writer.h>
#include <wirefem/scene/scene_reader.h>
#include <wirefem/simulation/simulation.h>
#include <wirefem/simulation/sweep.h>

#include <deal.II/base/mpi.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace wirefem::simulation
{
  namespace fs = std::filesystem;
  using scene::InputError;

  namespace
  {
    std::string trim(const std::string &s)
    {
      const auto a = s.find_first_not_of(" \t\r");
      const auto b = s.find_last_not_of(" \t\r");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    }

    std::vector<std::string> split(const std::string &s, const char sep)
    {
      std::vector<std::string> parts;
      std::istringstream in(s);
      std::string part;
      while (std::getline(in, part, sep))
        if (!trim(part).empty())
          parts.push_back(trim(part));
      return parts;
    }

    std::vector<double> numbers(const std::string &value, const std::string &where, const std::string &key)
    {
      std::vector<double> v;
      for (const auto &p : split(value, ','))
        {
          std::size_t used = 0;
          double x = 0.0;
          try
            {
              x = std::stod(p, &used);
            }
          catch (const std::exception &)
            {
              used = 0;
            }
          if (used != p.size() || !std::isfinite(x) || x < 0.0)
            throw InputError(where + ": " + key + ": '" + p + "' is not a non-negative number");
          v.push_back(x);
        }
      if (v.empty())
        throw InputError(where + ": " + key + ": needs at least one value");
      return v;
    }

    struct Case
    {
      int row, col, seed;
      double kappa, mu;
      std::string dir;
    };

    std::vector<Case> cases(const Sweep &s)
    {
      std::vector<Case> c;
      for (std::size_t i = 0; i < s.yield_curvatures.size(); ++i)
        for (std::size_t j = 0; j < s.static_coefficients.size(); ++j)
          for (int r = 0; r < s.realizations; ++r)
            {
              const int seed = s.first_seed + r;
              c.push_back(
                  {static_cast<int>(i), static_cast<int>(j), seed, s.yield_curvatures[i],
                   s.static_coefficients[j],
                   (fs::path(s.output_directory) /
                    fmt::format("kappa{}_mu{}_seed{}", s.yield_curvatures[i], s.static_coefficients[j], seed))
                       .string()});
            }
      return c;
    }

    /// The base scene's overrides that make it this case.
    std::vector<std::string> case_overrides(const Sweep &s, const Case &c)
    {
      auto o = s.overrides;
      o.push_back(fmt::format("Wire/Plasticity/Yield curvature={}", c.kappa));
      o.push_back(fmt::format("Contact/Friction/Static coefficient={}", c.mu));
      o.push_back(fmt::format("Injection/Seed={}", c.seed));
      return o;
    }

    /// The summary of a finished case, or null.
    nlohmann::json finished_summary(const Case &c)
    {
      const fs::path file = fs::path(c.dir) / "summary.json";
      if (!fs::exists(file))
        return nullptr;
      try
        {
          auto j = nlohmann::json::parse(std::ifstream(file));
          if (j.value("interrupted", true))
            return nullptr;
          return j;
        }
      catch (const nlohmann::json::exception &)
        {
          return nullptr;
        }
    }

    std::string json_number(const nlohmann::json &j, const char *key)
    {
      return j.contains(key) && j[key].is_number() ? fmt::format("{}", j[key].get<double>()) : std::string();
    }

    /// What the finished realizations of each cell share: their phases'
    /// votes and their series pooled for the fits.
    struct Pooled
    {
      explicit Pooled(const int n_cells)
        : votes(n_cells)
        , phi(n_cells)
        , loops(n_cells)
        , force(n_cells)
        , sum_phi_final(n_cells, 0.0)
      {
      }
      std::vector<std::map<std::string, int>> votes;
      std::vector<std::vector<double>> phi, loops, force;
      std::vector<double> sum_phi_final;
    };

    /// cells.csv: per cell the majority phase and the fits on the pooled
    /// realizations; fills the diagram's cells.
    void write_cells(const Sweep &s, const fs::path &out, const Pooled &pooled, io::PhaseDiagram &diagram)
    {
      const int n_rows = static_cast<int>(s.yield_curvatures.size()),
                n_cols = static_cast<int>(s.static_coefficients.size());
      std::ofstream cells((out / "cells.csv").string());
      cells
          << "kappa_theta,mu_st,runs,majority,fraction,gamma,gamma_error,phi_c,phi_c_error,beta,beta_error\n";
      for (int i = 0; i < n_rows; ++i)
        for (int jj = 0; jj < n_cols; ++jj)
          {
            const int cell = i * n_cols + jj;
            auto &d = diagram.cells[cell];
            for (const auto &[phase, n] : pooled.votes[cell])
              if (n > d.votes)
                {
                  d.votes = n;
                  d.majority = phase;
                }
            d.fraction = d.runs > 0 ? static_cast<double>(d.votes) / d.runs : 0.0;
            // Fits on the rows of the realizations pooled (neither fit
            // depends on the order of its rows).
            const auto g = analysis::fit_loop_exponent(pooled.phi[cell], pooled.loops[cell]);
            const double phi_end = d.runs > 0 ? pooled.sum_phi_final[cell] / d.runs : 0.0;
            const auto f = analysis::fit_jamming_force(pooled.phi[cell], pooled.force[cell], 0.5 * phi_end);
            auto value = [](const bool ok, const double v) {
              return ok ? fmt::format("{}", v) : std::string();
            };
            cells << fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", s.yield_curvatures[i],
                                 s.static_coefficients[jj], d.runs, d.majority, d.fraction,
                                 value(g.ok, g.gamma), value(g.ok, g.gamma_error), value(f.ok, f.phi_c),
                                 value(f.ok, f.phi_c_error), value(f.ok, f.beta), value(f.ok, f.beta_error));
          }
    }

    /// Rank 0: the tables and the picture from whatever cases are finished.
    void write_results(const Sweep &s, const std::vector<Case> &all)
    {
      const fs::path out(s.output_directory);
      std::ofstream rows((out / "sweep.csv").string());
      rows << "kappa_theta,mu_st,seed,status,phi_final,jammed,loops,morphology,symmetry,curvature_ratio,"
              "gamma,gamma_error,phi_c,beta,steps,wall_time_s,directory\n";
      const int n_rows = static_cast<int>(s.yield_curvatures.size()),
                n_cols = static_cast<int>(s.static_coefficients.size());
      io::PhaseDiagram diagram;
      diagram.kappa = s.yield_curvatures;
      diagram.mu = s.static_coefficients;
      diagram.cells.resize(n_rows * n_cols);
      Pooled pooled(n_rows * n_cols);
      auto &votes = pooled.votes;
      auto &pooled_phi = pooled.phi;
      auto &pooled_loops = pooled.loops;
      auto &pooled_force = pooled.force;
      auto &sum_phi_final = pooled.sum_phi_final;
      int finished = 0;
      for (const auto &c : all)
        {
          const auto j = finished_summary(c);
          const int cell = c.row * n_cols + c.col;
          if (j.is_null())
            {
              rows << fmt::format("{},{},{},not run,,,,,,,,,,,,,{}\n", c.kappa, c.mu, c.seed, c.dir);
              continue;
            }
          ++finished;
          const bool failed = j.value("failed", false);
          const std::string phase = failed ? std::string("failed") : j.value("morphology", "");
          if (failed) // a numerical limit or an energy balance error above 1%: shown, neither voting nor
                      // fitted
            {
              rows << fmt::format("{},{},{},failed,{},{},,,,,,,,,{},{},{}\n", c.kappa, c.mu, c.seed,
                                  json_number(j, "phi_final"), j.value("jammed", false),
                                  j.value("steps", 0ul), json_number(j, "wall_time_s"), c.dir);
              continue;
            }
          ++votes[cell][phase];
          ++diagram.cells[cell].runs;
          rows << fmt::format("{},{},{},finished,{},{},{},{},{},{},{},{},{},{},{},{},{}\n", c.kappa, c.mu,
                              c.seed, json_number(j, "phi_final"), j.value("jammed", false),
                              j.value("loops", 0), phase, json_number(j, "symmetry"),
                              json_number(j, "curvature_ratio"), json_number(j, "gamma"),
                              json_number(j, "gamma_error"), json_number(j, "phi_c"), json_number(j, "beta"),
                              j.value("steps", 0ul), json_number(j, "wall_time_s"), c.dir);
          const auto col =
              io::read_series_columns((fs::path(c.dir) / "series.csv").string(), {"phi", "loops", "force"});
          pooled_phi[cell].insert(pooled_phi[cell].end(), col[0].begin(), col[0].end());
          pooled_loops[cell].insert(pooled_loops[cell].end(), col[1].begin(), col[1].end());
          pooled_force[cell].insert(pooled_force[cell].end(), col[2].begin(), col[2].end());
          sum_phi_final[cell] += j.value("phi_final", 0.0);
        }

      write_cells(s, out, pooled, diagram);
      diagram.title = fmt::format("{}: {} of {} runs finished", fs::path(s.file).filename().string(),
                                  finished, all.size());
      io::write_phase_diagram(diagram, (out / "phase_diagram.png").string(),
                              (out / "phase_diagram.svg").string());
      std::cout << fmt::format("sweep: {} of {} cases finished; {}\n", finished, all.size(),
                               (out / "phase_diagram.png").string());
    }

    /// The keys of the sweep file's one 'subsection Sweep' with their values
    /// and where each was set ("file:line").
    void read_sweep_entries(const std::string &file, std::map<std::string, std::string> &values,
                            std::map<std::string, std::string> &where_of)
    {
      std::ifstream in(file);
      std::string raw;
      int line_no = 0;
      bool in_sweep = false, seen_section = false;
      const std::vector<std::string> keys = {"Base scene",      "Yield curvatures", "Static coefficients",
                                             "Realizations",    "First seed",       "Overrides",
                                             "Output directory"};
      while (std::getline(in, raw))
        {
          ++line_no;
          const std::string where = fmt::format("{}:{}", file, line_no);
          const auto hash = raw.find('#');
          const std::string l = trim(hash == std::string::npos ? raw : raw.substr(0, hash));
          if (l.empty())
            continue;
          if (l == "subsection Sweep" && !in_sweep)
            {
              in_sweep = seen_section = true;
              continue;
            }
          if (l == "end" && in_sweep)
            {
              in_sweep = false;
              continue;
            }
          if (!in_sweep || l.rfind("set ", 0) != 0 || l.find('=') == std::string::npos)
            throw InputError(where + ": '" + l + "': expected 'set Key = value' inside 'subsection Sweep'");
          const auto eq = l.find('=');
          const std::string key = trim(l.substr(4, eq - 4));
          if (std::find(keys.begin(), keys.end(), key) == keys.end())
            throw InputError(where + ": Sweep/" + key + ": no such key");
          values[key] = trim(l.substr(eq + 1));
          where_of[key] = where;
        }
      if (!seen_section || in_sweep)
        throw InputError(file + ": needs one 'subsection Sweep' ... 'end'");
    }
  } // namespace

  Sweep read_sweep(const std::string &file)
  {
    if (!fs::is_regular_file(file))
      throw InputError(file + ": cannot open the sweep file (no such file)");
    Sweep s;
    s.file = file;
    std::map<std::string, std::string> values, where_of;
    read_sweep_entries(file, values, where_of);
    auto need = [&](const std::string &key) {
      if (!values.count(key))
        throw InputError(file + ": Sweep/" + key + ": missing");
      return values[key];
    };
    const fs::path base = fs::path(file).parent_path() / need("Base scene");
    s.base_scene = base.string();
    if (!fs::is_regular_file(base))
      throw InputError(where_of["Base scene"] + ": Sweep/Base scene: '" + s.base_scene + "': no such file");
    s.yield_curvatures =
        numbers(need("Yield curvatures"), where_of["Yield curvatures"], "Sweep/Yield curvatures");
    s.static_coefficients =
        numbers(need("Static coefficients"), where_of["Static coefficients"], "Sweep/Static coefficients");
    auto integer = [&](const std::string &key, const int fallback, const int least) {
      if (!values.count(key))
        return fallback;
      std::size_t used = 0;
      int v = 0;
      try
        {
          v = std::stoi(values[key], &used);
        }
      catch (const std::exception &)
        {
          used = 0;
        }
      if (used != values[key].size() || v < least)
        throw InputError(where_of[key] + ": Sweep/" + key + ": '" + values[key] +
                         "' is not an integer >= " + std::to_string(least));
      return v;
    };
    s.realizations = integer("Realizations", 3, 1);
    s.first_seed = integer("First seed", 1, 0);
    if (values.count("Overrides"))
      s.overrides = split(values["Overrides"], ';');
    s.output_directory = values.count("Output directory") && !values["Output directory"].empty()
                             ? values["Output directory"]
                             : (fs::path("output") / fs::path(file).stem()).string();
    // Every case's scene must be valid before anything runs.
    for (const auto &c : cases(s))
      scene::read_scene(s.base_scene, case_overrides(s, c));
    return s;
  }

  int run_sweep(const Sweep &s)
  {
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
    const unsigned int size = dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    const auto all = cases(s);
    fs::create_directories(s.output_directory);
    int status = 0;
    int done = 0, skipped = 0;
    // Realization by realization: a sweep run in pieces has the whole grid
    // of its first seed before any cell's second one.
    std::vector<std::size_t> order(all.size());
    for (std::size_t k = 0; k < all.size(); ++k)
      order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](const std::size_t a, const std::size_t b) { return all[a].seed < all[b].seed; });
    for (std::size_t k = rank; k < order.size() && status != 130; k += size)
      {
        const auto &c = all[order[k]];
        if (!finished_summary(c).is_null())
          {
            ++skipped;
            continue;
          }
        auto o = case_overrides(s, c);
        o.push_back("Output/Directory=" + c.dir);
        o.push_back("Output/Progress=off");
        const auto scene = scene::read_scene(s.base_scene, o);
        const bool resume = fs::exists(fs::path(c.dir) / "checkpoint.bin");
        std::ostringstream log;
        auto *old = std::cout.rdbuf(log.rdbuf()); // one line per case instead of the run's report
        RunResult r;
        std::string error;
        try
          {
            // The sweep owns its case directories: a case neither finished
            // nor checkpointed (killed early) starts over.
            r = run(scene, {resume, !resume});
          }
        catch (const std::exception &e) // e.g. a checkpoint of other parameters: report, go on
          {
            error = e.what();
          }
        std::cout.rdbuf(old);
        if (!error.empty())
          {
            std::cerr << fmt::format("rank {}: kappa_theta {} mu_st {} seed {}: error: {}\n", rank, c.kappa,
                                     c.mu, c.seed, error);
            status = std::max(status, 3);
            continue;
          }
        std::cout << fmt::format(
                         "rank {}: kappa_theta {} mu_st {} seed {}: {}{}, phi {:.4f}, {} loops, {:.1f} s\n",
                         rank, c.kappa, c.mu, c.seed, r.interrupted ? "interrupted" : r.shape.phase,
                         resume ? " (resumed)" : "", r.phi_final, r.loops, r.wall_time_s)
                  << std::flush;
        if (r.interrupted)
          status = 130;
        else
          ++done;
      }
    std::cout << fmt::format("rank {}: ran {} cases, {} already finished\n", rank, done, skipped)
              << std::flush;
    // Everyone stops here (an interrupted rank too), then rank 0 tabulates.
    const int worst = dealii::Utilities::MPI::max(status, MPI_COMM_WORLD);
    if (rank == 0)
      write_results(s, all);
    MPI_Barrier(MPI_COMM_WORLD); // no rank leaves (and ends the job) before the tables are written
    return worst;
  }
} // namespace wirefem::simulation
