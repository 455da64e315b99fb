// Set-up = capstan: a wire lying on the cavity wall over a wrap angle, pushed
// along it against a compressive end force (validation case 5, the capstan
// law). Discrete model.
#pragma once

#include <wirefem/scene/parameters.h>
#include <wirefem/simulation/simulation.h>

namespace wirefem::simulation
{
  struct CapstanResult
  {
    bool finished = false;   ///< reached the end of the slide, or slipped (force control)
    double wrap_angle = 0.0; ///< angle covered by the frictional nodes (rad)
    int segments = 0;
    double push_force = 0.0;  ///< velocity control: mean compression where the wire leaves the pushed end
    double onset_force = 0.0; ///< force control: push force when the leading end began to slide
    unsigned long steps = 0;
    double wall_time_s = 0.0;
  };

  /// Runs the scene's capstan and writes summary.json, series.csv and
  /// profile.csv (compression along the wire at the end) into the output
  /// directory.
  /// The output directory follows run()'s rules (options.replace; no resume).
  CapstanResult run_capstan(const scene::Scene &scene, const RunOptions &options = {});
} // namespace wirefem::simulation
