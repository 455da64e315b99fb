#include <wirefem/fem/cantilever.h>
#include <wirefem/fem/rod_element.h>
#include <wirefem/fem/rod_numbering.h>

#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace wirefem::fem
{
  CantileverSolution solve_cantilever(const scene::Scene &s)
  {
    const auto &cl = s.cantilever;
    const auto &w = s.wire;
    const unsigned int p = s.fem.degree;
    const unsigned int n_cells = static_cast<unsigned int>(std::lround(cl.length / s.fem.element_length));
    const double h = cl.length / n_cells;
    const unsigned int n_nodes = n_cells * p + 1;
    const unsigned int n_dofs = 3 * n_nodes;

    const RodNumbering numbering{p, n_cells};
    auto global_node = [&numbering](unsigned int c, unsigned int a) { return numbering.node(c, a); };
    const auto shape = ElementShape::lagrange(p, h, p); // reduced integration, as the injection runs

    SectionProperties section;
    section.EA = w.axial_stiffness;
    section.GA = s.fem.formulation == scene::Formulation::kirchhoff
                     ? s.fem.kirchhoff_penalty * w.axial_stiffness
                     : s.fem.shear_stiffness;
    const auto &pl = w.plasticity;
    const bool plastic = s.plastic_bending();
    const auto law = plastic ? material::MomentCurvatureLaw(w.bending_stiffness, pl.yield_curvature,
                                                            pl.hardening_slope, pl.hardening)
                             : material::MomentCurvatureLaw(w.bending_stiffness);

    CantileverSolution out;
    out.effects = {"stretching",
                   s.fem.formulation == scene::Formulation::kirchhoff ? "shear constraint" : "shear",
                   "bending"};
    if (plastic)
      out.effects.push_back("plasticity");
    out.effects.push_back("end load");
    out.description =
        fmt::format("{} elements of degree {} ({}), h = {:g}", n_cells, p,
                    s.fem.formulation == scene::Formulation::kirchhoff ? "Kirchhoff" : "Reissner", h);

    std::vector<double> S(n_nodes);
    for (unsigned int c = 0; c < n_cells; ++c)
      for (unsigned int a = 0; a <= p; ++a)
        S[global_node(c, a)] = (c + shape.node_position[a]) * h;
    dealii::Vector<double> u(n_dofs);
    for (unsigned int k = 0; k < n_nodes; ++k)
      u[3 * k] = S[k];

    const unsigned int nd = 3 * (p + 1);
    std::vector<unsigned int> local(nd);
    auto local_dofs = [&](unsigned int c) { numbering.cell_dofs(c, local); };
    dealii::SparsityPattern sparsity;
    numbering.make_sparsity(sparsity);
    dealii::SparseMatrix<double> K(sparsity);
    dealii::Vector<double> R(n_dofs), du(n_dofs);

    std::vector<PointState> state(n_cells * shape.n_q), trial(state);
    ElementResult er;
    std::vector<double> ue(nd);
    const unsigned int tip = n_nodes - 1;
    const double scale = cl.force_scale(w.bending_stiffness);

    double assembled_plastic_work = 0.0; // of the last assembly, against the committed state
    // R = internal force - factor * end load, with the clamp's rows removed;
    // K its Jacobian (or only R when want_tangent is false).
    auto assemble = [&](const double factor, const bool want_tangent) {
      R = 0.0;
      if (want_tangent)
        K = 0.0;
      out.stretching = out.shear = out.bending = assembled_plastic_work = 0.0;
      for (unsigned int c = 0; c < n_cells; ++c)
        {
          local_dofs(c);
          for (unsigned int i = 0; i < nd; ++i)
            ue[i] = u[local[i]];
          evaluate_rod_element(shape, section, law, ue.data(), &state[c * shape.n_q], 0.0, want_tangent, er);
          std::copy(er.state.begin(), er.state.end(), trial.begin() + c * shape.n_q);
          out.stretching += er.axial_energy;
          out.shear += er.shear_energy;
          out.bending += er.bending_energy;
          assembled_plastic_work += er.plastic_work;
          for (unsigned int i = 0; i < nd; ++i)
            {
              R[local[i]] += er.residual[i];
              if (want_tangent)
                for (unsigned int j = 0; j < nd; ++j)
                  K.add(local[i], local[j], er.tangent[i * nd + j]);
            }
        }
      R[3 * tip] -= factor * cl.end_force_x;
      R[3 * tip + 1] -= factor * cl.end_force_y;
      R[3 * tip + 2] -= factor * cl.end_moment; // a moment on the section angle: conservative in the plane
      for (unsigned int i = 0; i < 3; ++i)
        {
          R[i] = 0.0;
          if (want_tangent)
            fix_dof(K, i);
        }
      return R.linfty_norm() / scale;
    };

    const double tol = cl.tolerance;
    // Newton's method at a load factor from the current u; false (u then
    // undefined) when it does not converge.
    auto newton = [&](const double target) {
      for (unsigned int it = 0; it < s.fem.maximum_iterations + 10; ++it)
        {
          const double r = assemble(target, true);
          out.residual = r;
          if (!std::isfinite(r))
            return false;
          if (r < tol)
            return true;
          dealii::SparseDirectUMFPACK solver;
          solver.initialize(K);
          solver.vmult(du, R);
          u -= du;
          ++out.iterations;
        }
      return false;
    };

    // The eigenvalue of smallest magnitude of the tangent K (assembled at a
    // converged state) and its mode, by inverse iteration. Past a
    // bifurcation it is negative on the branch that load control followed
    // through it (the straight rod above the Euler load).
    dealii::Vector<double> mode(n_dofs), tmp(n_dofs);
    auto lowest_eigenvalue = [&]() {
      dealii::SparseDirectUMFPACK solver;
      solver.initialize(K);
      for (unsigned int i = 3; i < n_dofs; ++i)
        mode[i] = 1.0 + 0.3 * std::sin(1.7 * i);
      mode[0] = mode[1] = mode[2] = 0.0;
      for (unsigned int k = 0; k < 60; ++k)
        {
          solver.vmult(tmp, mode);
          tmp[0] = tmp[1] = tmp[2] = 0.0;
          mode = tmp;
          mode /= mode.l2_norm();
        }
      K.vmult(tmp, mode);
      return (mode * tmp) / (mode * mode);
    };

    // Load increments: 0.1 to start, halved when Newton fails (at most 12
    // times), when a section turns too far, or when a stable state would be
    // followed by an unstable one; grown again after a success. A converged
    // state that is still unstable at an increment of 1e-4 is left along its
    // unstable mode, to the side of the transverse end force, and solved
    // again. So the run follows the stable branch connected to the unloaded
    // rod, as the dynamic relaxation of the discrete model does.
    double factor = 0.0, increment = 0.1, plastic_work = 0.0;
    int cuts = 0;
    bool was_stable = true;
    const auto points = scene::load_points(cl);
    std::size_t point = 0;
    while (point < points.size() && cuts <= 12)
      {
        const double goal = points[point];
        const double target =
            std::abs(goal - factor) <= increment ? goal : factor + (goal > factor ? increment : -increment);
        const dealii::Vector<double> u_start = u;
        bool ok = newton(target);
        if (ok)
          out.lowest_eigenvalue = lowest_eigenvalue();
        // From a stable state, an increment that lands on an unstable one has
        // jumped branches (or passed a critical point): redo it in halves.
        if (ok && out.lowest_eigenvalue < 0.0 && was_stable && increment > 1e-4)
          {
            u = u_start;
            increment *= 0.5;
            continue;
          }
        for (unsigned int attempt = 0; ok && out.lowest_eigenvalue < 0.0 && attempt < 4; ++attempt)
          {
            const double side =
                mode[3 * tip + 1] * (cl.end_force_y != 0.0 ? cl.end_force_y : 1.0) >= 0.0 ? 1.0 : -1.0;
            constexpr std::array<double, 4> amplitudes{{0.02, 0.1, 0.3, 0.6}};
            const double amplitude = amplitudes[attempt] * cl.length;
            const dealii::Vector<double> u_unstable = u;
            u.add(side * amplitude / mode.linfty_norm(), mode);
            ++out.unstable_states_left;
            ok = newton(target);
            if (!ok)
              {
                u = u_unstable;
                ok = newton(target);
                break;
              }
            out.lowest_eigenvalue = lowest_eigenvalue();
          }
        // An increment that turns a section by more than 0.25 rad is
        // redone in halves: with large increments Newton can land on another
        // branch of equilibria (past the Euler load, on the mirror image of
        // the one the imperfection selects).
        double turn = 0.0;
        for (unsigned int k = 0; ok && k < n_nodes; ++k)
          turn = std::max(turn, std::abs(u[3 * k + 2] - u_start[3 * k + 2]));
        if (!ok || (turn > 0.25 && increment > 1e-4))
          {
            u = u_start;
            increment *= 0.5;
            if (!ok && ++cuts > 12)
              break;
            continue;
          }
        state = trial;
        factor = target;
        plastic_work += assembled_plastic_work;
        was_stable = out.lowest_eigenvalue >= 0.0;
        increment = std::min(0.1, 1.5 * increment);
        ++out.increments;
        if (factor == goal)
          {
            out.history.push_back({{factor, u[3 * tip], u[3 * tip + 1], u[3 * tip + 2], plastic_work}});
            ++point;
          }
      }
    out.converged = point == points.size();
    out.S = S;
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        out.x.push_back(u[3 * k]);
        out.y.push_back(u[3 * k + 1]);
        out.theta.push_back(u[3 * k + 2]);
      }
    return out;
  }
} // namespace wirefem::fem
