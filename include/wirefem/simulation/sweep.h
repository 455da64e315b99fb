// A parameter sweep over (kappa_theta, mu_st) x realizations on MPI ranks:
// the phase diagram (docs/analysis.md).
#pragma once

#include <string>
#include <vector>

namespace wirefem::simulation
{
  /// What a sweep file (docs/analysis.md, "Phase diagram") describes.
  struct Sweep
  {
    std::string file;                   ///< the sweep file itself
    std::string base_scene;             ///< prm file every case starts from (relative to the sweep file)
    std::vector<std::string> overrides; ///< "Section/Key=value" applied to the base scene
    std::vector<double> yield_curvatures;
    std::vector<double> static_coefficients;
    int realizations = 3;
    int first_seed = 1;
    std::string output_directory; ///< default output/<sweep file name>
  };

  /// Reads a sweep file; throws scene::InputError naming file, line and key.
  Sweep read_sweep(const std::string &file);

  /// Runs the cases this MPI rank owns (round robin) that are not finished
  /// yet, each in <output>/kappa<value>_mu<value>_seed<seed>: a case with a
  /// summary.json of a run that was not interrupted is skipped (one stopped
  /// by a numerical limit counts as failed: shown, not voting, not fitted),
  /// one with a checkpoint is resumed. Rank 0 then writes sweep.csv (a row
  /// per case), cells.csv (per cell: majority phase, its fraction, fits on
  /// the pooled realizations) and phase_diagram.png/.svg. Returns the exit
  /// status: 0; 3 when a case could not run (reported, the others ran);
  /// 130 when interrupted (rerun to continue).
  int run_sweep(const Sweep &sweep);
} // namespace wirefem::simulation
