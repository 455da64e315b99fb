// Set-up = cantilever: a straight rod clamped at the origin and loaded at its
// free end by a dead force and a moment, relaxed to static equilibrium. The
// benchmarks of validation/ run through it.
#pragma once

#include <wirefem/scene/parameters.h>
#include <wirefem/simulation/simulation.h>

namespace wirefem::simulation
{
  struct CantileverResult
  {
    bool converged = false;
    double tip_x = 0.0, tip_y = 0.0; ///< free end (d)
    /// Direction angle of the rod at the free end: the last segment's angle
    /// plus half the turning angle at the last interior node (the segment's
    /// direction is the rod's at the segment midpoint).
    double tip_rotation = 0.0;
    double residual = 0.0; ///< largest nodal force / force scale at the end
    unsigned long steps = 0;
    double wall_time_s = 0.0;
  };

  /// Relaxes the scene's cantilever (discrete model) and writes summary.json
  /// and shape.csv (s, x, y per node) into the output directory.
  /// The output directory follows run()'s rules (options.replace; no resume).
  CantileverResult run_cantilever(const scene::Scene &scene, const RunOptions &options = {});
} // namespace wirefem::simulation
