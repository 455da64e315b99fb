// Set-up = cantilever with the rod FEM: the rod clamped at the origin (x, y
// and the section angle held) and loaded at its free end, solved statically
// by Newton's method with load increments.
#pragma once

#include <wirefem/scene/parameters.h>

#include <array>
#include <string>
#include <vector>

namespace wirefem::fem
{
  struct CantileverSolution
  {
    bool converged = false;
    std::vector<double> S, x, y, theta; ///< per node, in arc-length order
    double residual = 0.0;              ///< largest free residual / force scale
    unsigned int increments = 0;        ///< load increments taken
    unsigned long iterations = 0;       ///< Newton iterations in all
    std::string description;            ///< elements, degree, formulation
    /// Smallest-magnitude eigenvalue of the tangent at the end (negative:
    /// the state is unstable) and how many unstable states were left.
    double lowest_eigenvalue = 0.0;
    unsigned int unstable_states_left = 0;
    std::vector<std::string> effects;
    double stretching = 0.0, shear = 0.0, bending = 0.0;
    /// Per recorded equilibrium (scene::load_points): load factor, tip x, y,
    /// section angle, plastic work so far.
    std::vector<std::array<double, 5>> history;
  };

  CantileverSolution solve_cantilever(const scene::Scene &scene);
} // namespace wirefem::fem
