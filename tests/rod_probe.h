// The tests' and benchmarks' access to the rod FEM's assembly: the assembled
// tangent K at a step's predictor against central differences of the
// assembled residual, and one Newton iteration in its parts. Not part of
// the library: it reaches into RodModel::Impl (a friend).
#pragma once

#include "../source/fem/rod_model_impl.h"

#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <complex>
#include <utility>
#include <vector>

namespace wirefem::fem
{
  struct RodModelProbe
  {
    /// One Newton iteration of the rod's next implicit step, in its parts
    /// (for the benchmarks): at the step's predictor, assemble the residual
    /// and tangent (or the residual alone, as modified Newton does on kept
    /// factors), factorise the tangent (after the first time with the pivot
    /// order kept, as Newton does), solve with the factors. The model is
    /// not advanced.
    class NewtonIteration
    {
    public:
      explicit NewtonIteration(RodModel &rod)
        : m(*rod.impl)
        , rq(m.start_step(m.dt, x))
        , rhs(3 * (rq.last - rq.first))
        , dx(rhs.size())
      {
        assemble();
        m.newton_rhs(e, rq, rhs);
        factorise();
      }
      NewtonIteration(const NewtonIteration &) = delete;
      NewtonIteration &operator=(const NewtonIteration &) = delete;

      void assemble() { m.evaluate(rq, e); }
      /// The residual alone (an iteration of modified Newton on kept factors).
      void assemble_residual() { m.evaluate(rq.without_tangent(), e); }
      bool factorise() { return m.factorise_K(); }
      bool solve() { return m.solve_factorised(rhs, dx); }
      unsigned int unknowns() const { return rhs.size(); }
      /// Newton's right-hand side at the step's predictor.
      const dealii::Vector<double> &residual() const { return rhs; }
      /// Touching node-segment pairs between stretches of wire at the
      /// last assembly.
      std::size_t self_contacts() const { return e.pairs.size(); }
      /// Entries of the tangent's sparsity pattern.
      std::size_t entries() const { return m.K.values().size(); }
      /// The tangent of the last factorise() as sorted rows (CSR): the
      /// start of each row, the column and the value of each entry.
      void matrix(std::vector<int> &row_start, std::vector<int> &columns, std::vector<double> &values) const
      {
        row_start = m.lu.row_start();
        columns = m.lu.columns();
        values = m.K.values();
      }

    private:
      RodModel::Impl &m;
      StepState x;
      AssemblyRequest rq;
      dealii::Vector<double> rhs, dx;
      Evaluation e;
    };

    /// max |K - K_fd| / max |K| over the free dofs at x.u1, K assembled
    /// there (before the capstan roller's dof is rotated) and K_fd the
    /// central differences of the assembled residual, column by column.
    static double tangent_error(RodModel::Impl &m, const AssemblyRequest &rq, StepState &x)
    {
      // Central differences of the assembled residual, column by column,
      // against the tangent K assembled at x.u1 (before the capstan roller's
      // dof is rotated).
      const int lo = 3 * rq.first, nw = 3 * (rq.last - rq.first);
      Evaluation trial;
      AssemblyRequest raw = rq;
      raw.constrain = false;
      m.evaluate(raw, trial);
      double worst = 0, largest = 0;
      // Truncation (eps^2 times the third derivative) stays below rounding
      // (1e-16 / eps of the residual): contact along elements of degree 2
      // in a tight state showed 1.6e-6 at 1e-7 and 1.6e-4 at 1e-6.
      const double eps = 1e-8;
      for (int j = 0; j < nw; ++j)
        {
          const double keep = x.u1[lo + j];
          dealii::Vector<double> rp(nw);
          for (const double sign : {1.0, -1.0})
            {
              x.u1[lo + j] = keep + sign * eps;
              x.update();
              m.evaluate(raw.without_tangent(), trial);
              for (int i = 0; i < nw; ++i)
                rp[i] += sign * trial.residual[lo + i] / (2 * eps);
            }
          x.u1[lo + j] = keep;
          for (int i = 0; i < nw; ++i)
            {
              const double kij = m.K.el(i, j);
              worst = std::max(worst, std::abs(kij - rp[i]));
              largest = std::max(largest, std::abs(kij));
            }
        }
      x.update();
      return worst / largest;
    }

    /// At the predictor of the rod's next step: max |f - grad E| / max |f|
    /// over the free dofs, f the conservative forces assembled there and E
    /// the stored energy (axial, shear, bending, contact), its gradient by
    /// central differences. The model is not advanced.
    static double force_gradient_error(RodModel &rod)
    {
      auto &m = *rod.impl;
      StepState x;
      const AssemblyRequest rq = m.start_step(m.dt, x).without_tangent();
      Evaluation e, trial;
      m.evaluate(rq, e);
      const auto energy = [&] {
        m.evaluate(rq, trial);
        return trial.axial + trial.shear + trial.bending + trial.contact;
      };
      double worst = 0, largest = 0;
      const double eps = 1e-6;
      for (int i = 3 * rq.first; i < 3 * rq.last; ++i)
        {
          const double keep = x.u1[i];
          x.u1[i] = keep + eps;
          x.update();
          const double up = energy();
          x.u1[i] = keep - eps;
          x.update();
          const double down = energy();
          x.u1[i] = keep;
          x.update();
          worst = std::max(worst, std::abs(e.force[i] - (up - down) / (2 * eps)));
          largest = std::max(largest, std::abs(e.force[i]));
        }
      return worst / largest;
    }

    /// The linear solver's counts (factorisations, GMRES iterations).
    static const SparseDirect::Statistics &linear_statistics(const RodModel &rod)
    {
      return rod.impl->lu.statistics();
    }

    /// Steps that failed with kept factors and were tried again with an LU
    /// per Newton iteration.
    static unsigned long retried_steps(const RodModel &rod) { return rod.impl->retried_steps; }

    /// Steps cut because their largest overlap grew by more than
    /// FEM/Overlap growth, and the step cap they are measured against.
    static unsigned long overlap_cuts(const RodModel &rod) { return rod.impl->overlap_cuts; }
    static double step_cap(const RodModel &rod) { return rod.impl->dt_max; }
    /// The penalties per unit length the wall and the wire-wire contacts use.
    static std::pair<double, double> contact_stiffness(const RodModel &rod)
    {
      return {rod.impl->wall_settings.stiffness, rod.impl->self_settings.stiffness};
    }
    /// Newton's tolerance on the residual's max norm (force).
    static double newton_tolerance(const RodModel &rod) { return rod.impl->newton_tolerance; }
    /// FEM/Step error: the last step's local error estimate, the steps made
    /// again for it; the length of the next step, to be set by a test.
    static double error_estimate(const RodModel &rod) { return rod.impl->error_estimate; }
    /// FEM/Step energy error: the last step's energy estimate.
    static double energy_estimate(const RodModel &rod) { return rod.impl->energy_estimate; }
    static unsigned long error_cuts(const RodModel &rod) { return rod.impl->error_cuts; }
    static void set_next_step(RodModel &rod, const double step) { rod.impl->dt = step; }
    /// The wall springs of FEM/Friction law = spring (per node, at the last
    /// accepted step), writable so that a test can make a model forget them.
    static std::vector<contact::FrictionHistory> &wall_springs(RodModel &rod)
    {
      return rod.impl->wall_springs;
    }
    /// The self contacts' springs of FEM/Self friction law = spring, writable
    /// as the wall's.
    static PairSprings &self_springs(RodModel &rod) { return rod.impl->self_springs; }
    /// Quasi-static injection: snaps handed to dynamics, and whether the
    /// model is in such a dynamic phase now.
    static unsigned long snaps(const RodModel &rod) { return rod.impl->snaps; }
    static unsigned long pushes(const RodModel &rod) { return rod.impl->pushes; }
    /// A snap where the last one was, as if quasi-static Newton had failed
    /// again at the same place (from a quasi-static step).
    static void snap_again(RodModel &rod)
    {
      rod.impl->last_snap_at = rod.impl->injected_at(rod.impl->t);
      rod.impl->enter_dynamics();
    }
    static bool in_dynamic_phase(const RodModel &rod) { return rod.impl->dynamic_phase(); }

    /// The eigenvalues of the tangent of the next quasi-static step taken
    /// at the model's state now, an equilibrium at rest (friction sees no
    /// slip: a sticking contact resists as it would a small disturbance),
    /// without the dashpots, over the free dofs; without friction's part (the rod and the
    /// contacts' normal forces alone) when `friction` is false. The model
    /// is not advanced.
    static std::vector<std::complex<double>> tangent_eigenvalues_at_rest(RodModel &rod, const bool friction)
    {
      auto &m = *rod.impl;
      StepState x;
      const AssemblyRequest rq = m.start_step(m.dt, x);
      x.u1 = m.u;
      x.update();
      const auto wall = m.wall_settings, self = m.self_settings;
      const bool wall_spring = m.wall_spring, self_spring = m.self_spring, viscous = m.viscous;
      m.viscous = false; // a dashpot slows a disturbance down, it does not stop it
      if (!friction)
        {
          m.wall_settings.friction = m.self_settings.friction = false;
          m.wall_spring = m.self_spring = false;
        }
      Evaluation e;
      m.evaluate(rq, e);
      m.wall_settings = wall, m.self_settings = self;
      m.wall_spring = wall_spring, m.self_spring = self_spring, m.viscous = viscous;
      const int n = m.K.m();
      dealii::LAPACKFullMatrix<double> k(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = m.K.row_start()[i]; j < m.K.row_start()[i + 1]; ++j)
          k(i, m.K.columns()[j]) = m.K.values()[j];
      k.compute_eigenvalues();
      std::vector<std::complex<double>> lambda(n);
      for (int i = 0; i < n; ++i)
        lambda[i] = k.eigenvalue(i);
      return lambda;
    }
    /// Newton iterations (linear solves) of all attempts, cut ones included.
    static unsigned long newton_iterations(const RodModel &rod) { return rod.impl->newton_iterations; }

    /// What became of a pair pushed into contact within a step.
    struct PushedPair
    {
      bool found = false;            ///< a candidate pair outside K's pattern was pushed
      bool touching = false;         ///< it touches after the push
      bool in_pattern_after = false; ///< it is in K's pattern after the tangent was assembled
      double tangent_error = -1.0;   ///< as tangent_error(), after the push
      std::size_t pattern_pairs = 0; ///< pairs in K's pattern before the push
      std::size_t candidates = 0;    ///< the broad phase's pairs
    };

    /// One step of the model that, at its predictor, takes a candidate pair
    /// that is not in K's pattern, moves the first node of its first
    /// segment to 0.9 d from the middle of its second segment (in the
    /// step's unknowns, as a Newton iterate would) and checks the tangent
    /// there.
    static PushedPair step_pushing_a_pair_into_contact(RodModel &rod)
    {
      PushedPair r;
      auto &m = *rod.impl;
      bool done = false; // the probe runs at the first attempt only
      m.predictor_probe = [&](const AssemblyRequest &rq, StepState &x) {
        if (std::exchange(done, true))
          return;
        Evaluation e;
        m.evaluate(rq, e); // K's pattern at the predictor
        r.pattern_pairs = m.sp_pairs.size();
        r.candidates = m.broad.candidates().size();
        for (const auto &pr : m.broad.candidates())
          {
            if (std::binary_search(m.sp_pairs.begin(), m.sp_pairs.end(), pr) || pr.i < rq.first ||
                pr.j + 1 >= rq.last)
              continue;
            r.found = true;
            const Vec2 b0 = m.position(x.u1, pr.j), b1 = m.position(x.u1, pr.j + 1), mid = 0.5 * (b0 + b1);
            const Vec2 along = (1.0 / core::norm(b1 - b0)) * (b1 - b0), across{-along.y, along.x};
            const Vec2 a = m.position(x.u1, pr.i);
            const Vec2 to = mid + (core::dot(a - mid, across) >= 0.0 ? 0.9 : -0.9) * m.diameter * across;
            x.u1[3 * pr.i] = to.x;
            x.u1[3 * pr.i + 1] = to.y;
            x.update();
            r.touching = m.closer_than(x.u1, pr, m.diameter);
            r.tangent_error = tangent_error(m, rq, x);
            r.in_pattern_after = std::binary_search(m.sp_pairs.begin(), m.sp_pairs.end(), pr);
            break;
          }
      };
      rod.step();
      m.predictor_probe = nullptr;
      return r;
    }

    /// One step of the model that first checks the tangent at its
    /// predictor; returns the error (-1 if the step assembled nothing).
    static double step_checking_tangent(RodModel &rod)
    {
      double error = -1.0;
      auto &m = *rod.impl;
      bool done = false; // at the first attempt only (the probe must not reset itself while it runs)
      m.predictor_probe = [&](const AssemblyRequest &rq, StepState &x) {
        if (!std::exchange(done, true))
          error = tangent_error(m, rq, x);
      };
      rod.step();
      m.predictor_probe = nullptr;
      return error;
    }
  };
} // namespace wirefem::fem
