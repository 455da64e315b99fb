// One run of a scene: builds the model with the effects the scene calls for,
// steps it to jamming (or another stop), observes and writes the output of
// docs/output.md into the scene's output directory.
#pragma once

#include <wirefem/analysis/observables.h>
#include <wirefem/scene/parameters.h>

#include <string>
#include <vector>

namespace wirefem::simulation
{
  struct RunResult
  {
    bool jammed = false;
    /// stopped by a numerical limit (NaN, blow-up, storage), or ended with
    /// an energy balance error above 1% (see warnings)
    bool failed = false;
    bool interrupted = false; ///< SIGINT/SIGTERM: a checkpoint was written
    std::string stop_reason;
    double phi_final = 0.0;
    unsigned long steps = 0;
    double wall_time_s = 0.0;
    double energy_balance_error = 0.0; ///< relative, over the whole run
    double max_penetration = 0.0;      ///< largest overlap over the whole run (d)
    int loops = 0;
    analysis::Morphology shape;        ///< the classifier's label and numbers at the end
    std::vector<std::string> warnings; ///< the run's quality alarms (docs/output.md)
  };

  struct RunOptions
  {
    /// Continue from <output directory>/checkpoint.bin (written every
    /// Output/Checkpoint interval seconds and on SIGINT/SIGTERM).
    bool resume = false;
    /// Start over in an output directory that holds an earlier run: its
    /// files (docs/output.md) are deleted once the model is built. Without
    /// it (or resume) such a directory is refused.
    bool replace = false;
  };

  /// Runs the scene; creates the output directory. Progress and the active
  /// effects go to stderr/stdout. Throws scene::InputError if the output
  /// directory cannot be one or holds an earlier run (without resume or
  /// replace), or if a checkpoint to resume from is missing, damaged or
  /// belongs to other parameters; nothing on disk is changed then.
  RunResult run(const scene::Scene &scene, const RunOptions &options = {});
} // namespace wirefem::simulation
