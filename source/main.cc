// The wirefem executable: reads a scene, runs it, writes the output.
// Exit status: 0 finished, 2 bad input, 3 stopped by a numerical limit,
// 130 interrupted (a checkpoint was written; continue with --resume).
#include <wirefem/analysis/shape_io.h>
#include <wirefem/core/printable.h>
#include <wirefem/scene/scene_reader.h>
#include <wirefem/simulation/cantilever.h>
#include <wirefem/simulation/capstan.h>
#include <wirefem/simulation/simulation.h>
#include <wirefem/simulation/sweep.h>
#include <wirefem/version.h>

#include <CLI/CLI.hpp>
#include <deal.II/base/mpi.h>

#include <iostream>

namespace
{
  /// Parses the command line: -1 to go on, else the exit status (0 after
  /// --help or --version, 2 for a bad command line, reported as "NAME: error: ...").
  int parse(CLI::App &app, int argc, char **argv, const char *name)
  {
    try
      {
        app.parse(argc, argv);
        return -1;
      }
    catch (const CLI::Success &e) // --help, --version
      {
        return app.exit(e);
      }
    catch (const CLI::ParseError &e)
      {
        std::cerr << name << ": error: " << e.what() << " (see --help)\n";
        return 2;
      }
  }

  /// Runs `body` under the exit-status contract: bad input
  /// (core::InputError) 2, anything else 3, reported as "NAME: error:
  /// [CONTEXT: ]..." on one line (unless quiet: another MPI rank reports).
  template <typename Body>
  int with_exit_status(const std::string &name, const std::string &context, Body &&body,
                       const bool quiet = false)
  {
    try
      {
        return body();
      }
    catch (const wirefem::core::InputError &e)
      {
        if (!quiet)
          std::cerr << name << ": error: " << e.what() << '\n'; // printable already
        return 2;
      }
    catch (const std::exception &e)
      {
        if (!quiet)
          std::cerr << name << ": error: " << wirefem::core::printable(context + e.what()) << '\n';
        return 3;
      }
  }

  /// `wirefem analyze PATH`: loops, morphology, symmetry and phi of a shape
  /// (CSV file or a run's output directory) as JSON on stdout.
  int analyze(int argc, char **argv)
  {
    CLI::App app{"wirefem analyze: loops, morphology, symmetry and phi of a wire shape, as JSON.\n"
                 "PATH is a CSV file (x,y per row in arc-length order) or a run's output directory."};
    std::string path;
    wirefem::analysis::ShapeOptions options;
    app.add_option("path", path, "CSV file or output directory")->required();
    app.add_option("--diameter", options.diameter, "Wire diameter in the units of the file (default 1)")
        ->check(CLI::PositiveNumber);
    app.add_option("--radius", options.cavity_radius, "Cavity radius in the units of the file")
        ->check(CLI::PositiveNumber);
    if (const int status = parse(app, argc, argv, "wirefem analyze"); status >= 0)
      return status;
    return with_exit_status("wirefem analyze", path + ": ", [&] {
      const auto wire = wirefem::analysis::read_shape(path, options);
      std::cout << wirefem::analysis::analysis_report(wire, wire.cavity_radius > 0.0) << '\n';
      return 0;
    });
  }

  /// `[mpirun -np N] wirefem sweep FILE.prm`: the phase-diagram sweep.
  int sweep(int argc, char **argv)
  {
    CLI::App app{"wirefem sweep: runs a grid over (kappa_theta, mu_st) x realizations on the MPI ranks\n"
                 "(mpirun -np N wirefem sweep FILE.prm); rerun to continue an interrupted sweep."};
    std::string file;
    app.add_option("file", file, "Sweep file (docs/analysis.md, Phase diagram)")->required();
    if (const int status = parse(app, argc, argv, "wirefem sweep"); status >= 0)
      return status;
    // Every rank reads the same file and meets the same error: rank 0 says it.
    const bool quiet = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0;
    wirefem::simulation::Sweep sweep;
    const int read = with_exit_status(
        "wirefem sweep", "",
        [&] {
          sweep = wirefem::simulation::read_sweep(file);
          return -1;
        },
        quiet);
    if (read >= 0)
      return read;
    return with_exit_status("wirefem sweep", "", [&] { return wirefem::simulation::run_sweep(sweep); });
  }
} // namespace

int main(int argc, char **argv)
{
  if (argc > 1 && std::string(argv[1]) == "analyze")
    return analyze(argc - 1, argv + 1);
  // Trilinos (the FEM's matrices and direct solver) needs MPI; one thread.
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc > 1 && std::string(argv[1]) == "sweep")
    return sweep(argc - 1, argv + 1);
  CLI::App app{"wirefem: a wire pushed from two channels into a circular cavity until it jams.\n"
               "Example: wirefem prm/classic.prm --set \"Contact/Friction/Static coefficient=0.2\"\n"
               "Analysis of a shape or a finished run: wirefem analyze PATH (see wirefem analyze --help)\n"
               "Phase-diagram sweep on MPI ranks: mpirun -np N wirefem sweep FILE.prm"};
  std::string prm_file;
  std::vector<std::string> overrides;
  bool print = false;
  bool resume = false, replace = false;
  app.add_option("scene", prm_file, "Scene file (.prm, deal.II ParameterHandler format)");
  app.add_option("--set", overrides, "Override a key: \"Section/Key=value\" (repeatable)")
      ->allow_extra_args(false)
      ->take_all();
  app.set_version_flag("--version", std::string("wirefem ") + wirefem::version());
  app.add_flag("--print-parameters", print, "Print every key with its default and documentation");
  app.add_flag("--resume", resume, "Continue an interrupted run from its output directory's checkpoint.bin");
  app.add_flag("--replace", replace,
               "Start over in an output directory that holds an earlier run, deleting that run's files");
  if (const int status = parse(app, argc, argv, "wirefem"); status >= 0)
    return status;
  if (print)
    {
      wirefem::scene::print_parameters(std::cout);
      return 0;
    }
  if (prm_file.empty())
    {
      std::cerr << "wirefem: error: no scene file given (see --help)\n";
      return 2;
    }
  return with_exit_status("wirefem", "", [&] {
    const auto scene = wirefem::scene::read_scene(prm_file, overrides);
    if (scene.setup == wirefem::scene::Setup::cantilever)
      return wirefem::simulation::run_cantilever(scene, {resume, replace}).converged ? 0 : 3;
    if (scene.setup == wirefem::scene::Setup::capstan)
      return wirefem::simulation::run_capstan(scene, {resume, replace}).finished ? 0 : 3;
    const auto result = wirefem::simulation::run(scene, {resume, replace});
    return result.interrupted ? 130 : (result.failed ? 3 : 0);
  });
}
