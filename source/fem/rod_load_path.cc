// The clamp loading's static path (Set-up = cantilever): load increments,
// each a quasi-static step of the rod's Newton solver (rod_stepper.cc).
#include "rod_model_impl.h"

#include <cstdlib>

namespace wirefem::fem
{
  bool RodModel::Impl::static_step(const double factor)
  {
    load_factor = factor;
    bool ok = false;
    try
      {
        // Without inertia, dashpots or friction the step length does not
        // enter the equilibrium.
        ok = solve_step(1.0) == StepOutcome::converged;
      }
    catch (const dealii::ExceptionBase &)
      {
        ok = false;
      }
    if (std::getenv("WIREFEM_NEWTON_LOG"))
      std::cerr << fmt::format("load factor {:.6g}: {}; residuals{}\n", factor, ok ? "converged" : "failed",
                               residual_history());
    path.residual = history.empty() ? INFINITY : history.back() / force_scale;
    if (ok)
      {
        // A static path has no rates: the next predictor is the state itself.
        v = 0.0;
        a = 0.0;
      }
    return ok;
  }

  double RodModel::Impl::lowest_eigenvalue(dealii::Vector<double> &mode)
  {
    // K holds the tangent at the committed state (the last assembly of the
    // converged Newton iteration). Past a bifurcation the eigenvalue is
    // negative on the branch that load control followed through it (the
    // straight rod above the Euler load).
    const unsigned int n = K.m();
    mode.reinit(n);
    dealii::Vector<double> tmp(n);
    if (!factorise_K())
      return 0.0; // singular: at a critical point
    for (unsigned int j = 0; j < n; ++j)
      mode[j] = 1.0 + 0.3 * std::sin(1.7 * (j + 3));
    for (unsigned int k = 0; k < 60; ++k)
      {
        if (!solve_factorised(mode, tmp))
          return 0.0;
        mode = tmp;
        mode /= mode.l2_norm();
      }
    K.vmult(mode.data(), tmp.data());
    return (mode * tmp) / (mode * mode);
  }

  core::Equilibrium RodModel::Impl::follow_load(const double goal)
  {
    // Increments of 0.1 at most, halved when Newton fails (at most 12 times
    // per load point), when a section turns too far, or when a stable state
    // would be followed by an unstable one; grown again after a success. A
    // converged state that is still unstable at an increment of 1e-4 is left
    // along its unstable mode, to the side of the transverse end force, and
    // solved again. So the path is the stable branch connected to the
    // unloaded rod, the one the chain's dynamic relaxation falls onto.
    dealii::Vector<double> mode;
    int cuts = 0;
    while (load_factor != goal && cuts <= 12)
      {
        const double target = std::abs(goal - load_factor) <= path.increment
                                  ? goal
                                  : load_factor + (goal > load_factor ? path.increment : -path.increment);
        const Committed start = committed();
        bool ok = static_step(target);
        if (ok)
          path.lowest_eigenvalue = lowest_eigenvalue(mode);
        // From a stable state, an increment that lands on an unstable one has
        // jumped branches (or passed a critical point): redo it in halves.
        if (ok && path.lowest_eigenvalue < 0.0 && path.was_stable && path.increment > 1e-4)
          {
            restore(start);
            path.increment *= 0.5;
            continue;
          }
        if (ok && path.lowest_eigenvalue < 0.0)
          ok = leave_unstable_state(start, target, mode);
        // An increment that turns a section by more than 0.25 rad is redone
        // in halves: with large increments Newton can land on another branch
        // of equilibria (past the Euler load, on the mirror image of the one
        // the imperfection selects).
        double turn = 0.0;
        for (unsigned int k = 0; ok && k < n_nodes; ++k)
          turn = std::max(turn, std::abs(u[3 * k + 2] - start.u[3 * k + 2]));
        if (!ok || (turn > 0.25 && path.increment > 1e-4))
          {
            restore(start);
            path.increment *= 0.5;
            if (!ok)
              ++cuts;
            continue;
          }
        path.was_stable = path.lowest_eigenvalue >= 0.0;
        path.increment = std::min(0.1, 1.5 * path.increment);
        ++path.increments;
      }

    return equilibrium(load_factor == goal);
  }

  bool RodModel::Impl::leave_unstable_state(const Committed &start, const double target,
                                            dealii::Vector<double> &mode)
  {
    // Along the unstable mode, to the side of the transverse end force, by
    // growing amplitudes; back to the unstable state when Newton fails there.
    const auto &cl = scene.cantilever;
    const int tip_y = 3 * (n_nodes - 2) + 1; // the last node's y in the free dofs, which start at node 1
    for (unsigned int attempt = 0; path.lowest_eigenvalue < 0.0 && attempt < 4; ++attempt)
      {
        const double side = mode[tip_y] * (cl.end_force_y != 0.0 ? cl.end_force_y : 1.0) >= 0.0 ? 1.0 : -1.0;
        constexpr double amplitudes[4] = {0.02, 0.1, 0.3, 0.6};
        const dealii::Vector<double> u_unstable = u;
        const double shift = side * amplitudes[attempt] * cl.length / mode.linfty_norm();
        restore(start);
        for (unsigned int j = 0; j < mode.size(); ++j)
          u[3 + j] = u_unstable[3 + j] + shift * mode[j];
        ++path.unstable_states_left;
        if (!static_step(target))
          {
            restore(start);
            u = u_unstable;
            return static_step(target);
          }
        path.lowest_eigenvalue = lowest_eigenvalue(mode);
      }
    return true;
  }

  core::Equilibrium RodModel::Impl::equilibrium(const bool converged) const
  {
    const unsigned int tip = n_nodes - 1;
    core::Equilibrium out;
    out.converged = converged;
    out.residual = path.residual;
    out.tip_x = u[3 * tip];
    out.tip_y = u[3 * tip + 1];
    out.tip_rotation = u[3 * tip + 2]; // the section angle at the loaded end
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        out.S.push_back(node_S[k]);
        out.x.push_back(u[3 * k]);
        out.y.push_back(u[3 * k + 1]);
      }
    return out;
  }
} // namespace wirefem::fem
