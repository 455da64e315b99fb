// Set-up = capstan with the rod FEM (validation case 5): a rod lying on the
// cavity wall over a wrap angle, its trailing end slid along the wall at the
// push speed (polar and section angle prescribed, its radius free or held:
// Capstan/Trailing end), its leading end
// loaded by a compressive follower force and the moment that holds it at the
// wall's curvature. Quasi-static: each step is an equilibrium of the elastic
// rod, the penalty wall and the rate-dependent friction of the contact
// element (velocities are backward differences over the step), solved by
// Newton's method with a direct solver. Force control needs FEM/Friction
// law = spring: the regularised law creeps below the threshold velocity, so
// it has no sharp stick/slip threshold to measure. Under force control the
// trailing end is free and pushed by a follower force that rises at
// Capstan/Force rate; the wire has slipped once its leading end moved
// Capstan/Slip distance, or when no equilibrium exists at a larger push
// (the step is cut below FEM/Minimum time step): the last push that had one.
#pragma once

#include <wirefem/scene/parameters.h>

#include <array>
#include <string>
#include <vector>

namespace wirefem::fem
{
  struct CapstanSolution
  {
    bool finished = false;
    std::string description; ///< elements, degree, formulation
    unsigned int elements = 0;
    double wrap_angle = 0.0; ///< angle covered by the frictional contacts (rad)
    double push_force = 0.0; ///< axial force at the trailing end, averaged over the second half of the slide
    double push_force_peak = 0.0;
    double onset_force = 0.0;               ///< force control: push at which the wire slipped
    bool onset_without_equilibrium = false; ///< ... found as the last push with an equilibrium
    /// mu(V) tanh(V / v_th) of the contact law at the push speed V: the
    /// coefficient steady sliding mobilises.
    double sliding_coefficient = 0.0;
    double max_penetration = 0.0; ///< largest wall overlap / d
    double time = 0.0, time_step = 0.0;
    unsigned long steps = 0, newton_iterations = 0;
    unsigned int step_cuts = 0;
    /// time, pushed distance, slide of the leading end, push force,
    /// compression at the first quadrature point
    std::vector<std::array<double, 5>> series;
    /// angle from the leading end, compression (quadrature points, averaged
    /// like the push force)
    std::vector<std::array<double, 2>> profile;
  };

  /// With tangent_check, the assembled tangent of the first step (at its
  /// second Newton iterate, where the friction is engaged) is compared with
  /// central differences of the residual: max |K - K_fd| / max |K| (tests).
  CapstanSolution solve_capstan(const scene::Scene &scene, double *tangent_check = nullptr);
} // namespace wirefem::fem
