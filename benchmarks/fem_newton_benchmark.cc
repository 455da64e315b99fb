// Cost of one Newton iteration of the rod FEM, in its parts: assembly of
// the residual and tangent, assembly of the residual alone (modified
// Newton's iterations on kept factors: residual + solve), refactorisation
// of the tangent (KLU, pivot order kept), solve with the factors; on states
// of the classic scene (prm/classic.prm, seed 1) at f = 10, 25, 50 and
// phi = 0.3, 0.45 (0.37 at f = 50, which jams at 0.379). Each benchmark
// reports the unknowns and the time per unknown (per_unknown).
// The chain's step at f = 25 is wirefem_benchmarks' `full`. On the densest
// state of each cavity, fem_factorisation compares the FEM's factorisation
// (KLU, AMD on the graph of the nodes: `factorisation` above) with AMD on
// the dofs, COLAMD, UMFPACK and Eigen's SparseLU (counter fill: entries of
// the factors over the matrix's), and with the whole solve by GMRES on the
// LU of the tangent's band (FEM/Linear solver = band) to 1e-3 and 1e-9 of
// the right-hand side (counter gmres_iterations).
//
// The states are made once by running the FEM from the start and are kept
// in WIREFEM_FEM_STATES (default: fem-states in the working directory) as
// the model's checkpoint; a state that is being made is saved every 2,000
// steps and resumed from there, so f = 50 (hours) can be made in pieces.
// WIREFEM_FEM_SIZES limits the cavities (default "10 25 50").
#include <wirefem/analysis/observables.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/scene/scene_reader.h>

#include "../tests/rod_probe.h"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <klu.h>
#include <umfpack.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

namespace
{
  using namespace wirefem;
  namespace fs = std::filesystem;

  /// The packing densities of the states of a cavity, from the highest:
  /// 0.45 and 0.3, but the classic scene at f = 50 (seed 1) jams at 0.379,
  /// so its dense state is at 0.37, in the final climb of the inlet force.
  std::array<double, 2> densities(const int radius)
  {
    return {{radius >= 50 ? 0.37 : 0.45, 0.3}};
  }

  scene::Scene classic(const int radius)
  {
    return scene::read_scene(
        WIREFEM_SOURCE_DIR "/prm/classic.prm",
        {"Model=fem", fmt::format("Cavity/Radius={}", radius), "Injection/Seed=1", "Output/Progress=off"});
  }

  void save(const fem::RodModel &m, const fs::path &file)
  {
    const fs::path part = file.string() + ".tmp";
    {
      std::ofstream out(part, std::ios::binary);
      m.save(out);
      if (!out)
        throw std::runtime_error("cannot write " + part.string());
    }
    fs::rename(part, file);
  }

  /// The FEM on the classic scene at this radius, at packing density phi:
  /// from the kept state, or run there (resuming a partial run).
  std::unique_ptr<fem::RodModel> state(const int radius, const double phi)
  {
    const fs::path dir = std::getenv("WIREFEM_FEM_STATES") ? std::getenv("WIREFEM_FEM_STATES") : "fem-states";
    fs::create_directories(dir);
    const auto kept = [&](const double density) {
      return dir / fmt::format("classic_f{}_phi{}.bin", radius, density);
    };
    const fs::path file = kept(phi);
    const fs::path partial = dir / fmt::format("classic_f{}_phi{}.partial", radius, phi);
    auto m = std::make_unique<fem::RodModel>(classic(radius));
    // Start from the state itself, its partial run, or the kept state of
    // the same cavity at the highest lower density.
    fs::path from = fs::exists(file) ? file : partial;
    for (const double lower : densities(radius))
      if (!fs::exists(from) && lower < phi)
        from = kept(lower);
    if (fs::exists(from))
      {
        std::ifstream in(from, std::ios::binary);
        try
          {
            m->load(in);
          }
        catch (const std::runtime_error &e)
          {
            // A state of an earlier format: made again from the start.
            std::cerr << fmt::format("{}: {}; made again\n", from.string(), e.what());
            m = std::make_unique<fem::RodModel>(classic(radius));
            fs::remove(from);
          }
      }
    if (fs::exists(file))
      return m;
    std::cerr << fmt::format("making {} (FEM from phi {:.3f})\n", file.string(),
                             analysis::packing_density(m->injected_length(), radius));
    while (analysis::packing_density(m->injected_length(), radius) < phi)
      {
        m->step();
        if (m->n_steps() % 2000 == 0)
          save(*m, partial);
      }
    save(*m, file);
    fs::remove(partial);
    return m;
  }

  enum class Part
  {
    assembly, ///< residual and tangent
    residual, ///< the residual alone (modified Newton on kept factors)
    factorisation,
    solve
  };

  void newton_iteration(benchmark::State &st, const int radius, const double phi, const Part part)
  {
    auto m = state(radius, phi);
    fem::RodModelProbe::NewtonIteration it(*m);
    for (auto _ : st)
      switch (part)
        {
        case Part::assembly:
          it.assemble();
          break;
        case Part::residual:
          it.assemble_residual();
          break;
        case Part::factorisation:
          benchmark::DoNotOptimize(it.factorise());
          break;
        case Part::solve:
          benchmark::DoNotOptimize(it.solve());
          break;
        }
    st.counters["unknowns"] = it.unknowns();
    st.counters["entries"] = static_cast<double>(it.entries());
    // Contact dominates the assembly: its cost per unknown follows the
    // touching pairs per node, which differ from state to state.
    st.counters["contacts_per_node"] = 3.0 * static_cast<double>(it.self_contacts()) / it.unknowns();
    st.counters["per_unknown"] = benchmark::Counter(
        it.unknowns(), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  }

  // The factorisation of the same tangent by the sparse LU codes at hand,
  // as Newton would use them: the analysis once, then a numeric
  // factorisation per iteration (KLU: with the pivot order kept). KLU and
  // UMFPACK read columns, so they factorise A^T, at A's cost.
  enum class Solver
  {
    klu_dofs,   ///< SparseDirect with AMD on the graph of the dofs
    klu_colamd, ///< KLU with COLAMD
    umfpack,    ///< UMFPACK (multifrontal)
    eigen,      ///< Eigen's SparseLU (supernodal), COLAMD
    band_loose, ///< SparseDirect::solve_band to 1e-3 of |b| (an inexact Newton step)
    band_tight  ///< SparseDirect::solve_band to 1e-9 of |b|
  };

  void factorisation_by(benchmark::State &st, const int radius, const double phi, const Solver solver)
  {
    auto m = state(radius, phi);
    fem::RodModelProbe::NewtonIteration it(*m);
    std::vector<int> row_start, columns;
    std::vector<double> values;
    it.matrix(row_start, columns, values);
    const int n = static_cast<int>(row_start.size()) - 1;
    const auto entries = static_cast<double>(columns.size());
    double factor_entries = 0.0;
    switch (solver)
      {
      case Solver::klu_dofs:
        {
          fem::SparseDirect lu;
          lu.analyse(n, row_start, columns, 1);
          lu.factorise(values);
          factor_entries = lu.statistics().factor_entries;
          for (auto _ : st)
            benchmark::DoNotOptimize(lu.factorise(values));
          break;
        }
      case Solver::klu_colamd:
        {
          klu_common common;
          klu_defaults(&common);
          common.btf = 0;
          common.ordering = 1;
          klu_symbolic *symbolic = klu_analyze(n, row_start.data(), columns.data(), &common);
          klu_numeric *numeric =
              klu_factor(row_start.data(), columns.data(), values.data(), symbolic, &common);
          factor_entries = static_cast<double>(numeric->lnz + numeric->unz);
          for (auto _ : st)
            benchmark::DoNotOptimize(
                klu_refactor(row_start.data(), columns.data(), values.data(), symbolic, numeric, &common));
          klu_free_numeric(&numeric, &common);
          klu_free_symbolic(&symbolic, &common);
          break;
        }
      case Solver::umfpack:
        {
          double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
          umfpack_di_defaults(control);
          void *symbolic = nullptr, *numeric = nullptr;
          umfpack_di_symbolic(n, n, row_start.data(), columns.data(), values.data(), &symbolic, control,
                              info);
          for (auto _ : st)
            {
              if (numeric)
                umfpack_di_free_numeric(&numeric);
              umfpack_di_numeric(row_start.data(), columns.data(), values.data(), symbolic, &numeric, control,
                                 info);
            }
          factor_entries = info[UMFPACK_LNZ] + info[UMFPACK_UNZ];
          umfpack_di_free_numeric(&numeric);
          umfpack_di_free_symbolic(&symbolic);
          break;
        }
      case Solver::band_loose:
      case Solver::band_tight:
        {
          // The whole solve, band LU and GMRES: it replaces factorisation
          // and solve.
          fem::SparseDirect lu;
          lu.analyse(n, row_start, columns, 3);
          const auto &r = it.residual();
          const std::vector<double> b(r.begin(), r.end());
          double norm = 0.0;
          for (const double v : b)
            norm += v * v;
          const double tolerance = (solver == Solver::band_loose ? 1e-3 : 1e-9) * std::sqrt(norm);
          std::vector<double> x;
          for (auto _ : st)
            benchmark::DoNotOptimize(lu.solve_band(values, b, x, tolerance, 60, 1));
          const auto &s = lu.statistics();
          st.counters["gmres_iterations"] = static_cast<double>(s.band_iterations) / s.band_solves;
          st.counters["direct"] = static_cast<double>(s.band_refactorised);
          break;
        }
      case Solver::eigen:
        {
          using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
          const Eigen::Map<const Matrix> a(n, n, static_cast<int>(columns.size()), row_start.data(),
                                           columns.data(), values.data());
          const Eigen::SparseMatrix<double, Eigen::ColMajor, int> by_columns = a;
          Eigen::SparseLU<Eigen::SparseMatrix<double, Eigen::ColMajor, int>, Eigen::COLAMDOrdering<int>> lu;
          lu.analyzePattern(by_columns);
          lu.factorize(by_columns);
          factor_entries = static_cast<double>(lu.nnzL() + lu.nnzU());
          for (auto _ : st)
            lu.factorize(by_columns);
          break;
        }
      }
    st.counters["unknowns"] = n;
    st.counters["entries"] = entries;
    {
      fem::SparseDirect blocks;
      blocks.analyse(n, row_start, columns, 3);
      st.counters["lu_work_per_entry"] = blocks.lu_work() / entries;
    }
    st.counters["fill"] = factor_entries / entries;
    st.counters["per_unknown"] =
        benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  }
} // namespace

int main(int argc, char **argv)
{
  std::istringstream sizes(std::getenv("WIREFEM_FEM_SIZES") ? std::getenv("WIREFEM_FEM_SIZES") : "10 25 50");
  const std::pair<Part, const char *> parts[] = {{Part::assembly, "assembly"},
                                                 {Part::residual, "residual"},
                                                 {Part::factorisation, "factorisation"},
                                                 {Part::solve, "solve"}};
  for (int radius; sizes >> radius;)
    for (const double phi : {densities(radius)[1], densities(radius)[0]})
      for (const auto &[part, name] : parts)
        benchmark::RegisterBenchmark(
            fmt::format("fem_newton/f{}/phi{}/{}", radius, phi, name).c_str(),
            [radius, phi, part = part](benchmark::State &st) { newton_iteration(st, radius, phi, part); })
            ->Unit(benchmark::kMicrosecond);
  // The other sparse LU codes, on the densest state of each cavity.
  const std::pair<Solver, const char *> solvers[] = {{Solver::klu_dofs, "klu_amd_dofs"},
                                                     {Solver::klu_colamd, "klu_colamd"},
                                                     {Solver::umfpack, "umfpack"},
                                                     {Solver::eigen, "eigen_sparselu"},
                                                     {Solver::band_loose, "band_gmres_1e-3"},
                                                     {Solver::band_tight, "band_gmres_1e-9"}};
  sizes.clear();
  sizes.seekg(0);
  for (int radius; sizes >> radius;)
    for (const auto &[solver, name] : solvers)
      benchmark::RegisterBenchmark(
          fmt::format("fem_factorisation/f{}/phi{}/{}", radius, densities(radius)[0], name).c_str(),
          [radius, solver = solver](benchmark::State &st) {
            factorisation_by(st, radius, densities(radius)[0], solver);
          })
          ->Unit(benchmark::kMicrosecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
