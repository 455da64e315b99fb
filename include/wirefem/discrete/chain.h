// The discrete model's state: point masses on a chain at rest spacing
// lambda_0. Nodes live in arrays indexed by a stable storage index; the
// active nodes are [first, last). Injection grows the chain at both ends
// (first decreases, last increases), so indices never shift and contact
// history keyed by them stays valid.
//
// The n_prescribed outermost nodes at the first end and n_prescribed_last at
// the last sit in the channels and move with the injection; all others are
// free (with one channel the last end is free).
#pragma once

#include <wirefem/core/vec2.h>

#include <iosfwd>
#include <algorithm>
#include <cmath>
#include <vector>

namespace wirefem::discrete
{
  struct Chain
  {
    double lambda0 = 1.0;      ///< rest length of a segment (d)
    double node_mass = 1.0;    ///< rho A lambda_0
    int first = 0;             ///< first active node (storage index)
    int last = 0;              ///< one past the last active node
    int n_prescribed = 2;      ///< nodes held by the channel at the first end
    int n_prescribed_last = 2; ///< and at the last end (0: a free end)

    std::vector<core::Vec2> x;         ///< positions (d)
    std::vector<core::Vec2> v;         ///< velocities (d / time)
    std::vector<core::Vec2> f;         ///< forces of the current step
    std::vector<double> contact_force; ///< sum of contact normal forces per node (output)

    explicit Chain(int capacity = 0)
      : x(capacity)
      , v(capacity)
      , f(capacity)
      , contact_force(capacity)
    {
    }
    int capacity() const { return static_cast<int>(x.size()); }
    int n_active() const { return last - first; }
    bool is_free(const int k) const { return k >= first + n_prescribed && k < last - n_prescribed_last; }
  };

  /// The explicit time step: a fraction `factor` of the stability limit.
  /// omega2 bounds the squared highest frequency of the springs; `rate`
  /// the highest decay rate c/m of the dashpots, which must satisfy
  /// rate dt < 2 on their own. The rotational dashpot's rate,
  /// 16 c_r / (m lambda_0^2), grows like 1/lambda_0^3, faster than the
  /// bending frequency, so it sets the step on fine chains (at lambda_0 =
  /// 1/16 d with c_r = 0.5 the stiffness limit alone let runs blow up).
  inline double explicit_time_step(const double factor, const double omega2, const double rate)
  {
    return factor * 2.0 / std::max(std::sqrt(omega2), rate);
  }

  /// What the force terms of one step report: potential energies at the
  /// current state and the increments of dissipated work over the step.
  struct StepEnergy
  {
    double stretching = 0.0;      ///< sum 1/2 k1 (lambda - lambda_0)^2
    double bending = 0.0;         ///< sum 1/2 k2 (zeta - zeta_p)^2
    double contact = 0.0;         ///< penalty energy 1/2 k_n overlap^2
    double friction_stored = 0.0; ///< energy in sticking springs 1/2 k_t u^2
    double load_potential = 0.0;  ///< potential of external loads (cantilever set-up)
    double damping_work = 0.0;    ///< dissipated by viscous damping this step
    double plastic_work = 0.0;    ///< plastic work this step
    double friction_work = 0.0;   ///< work dissipated by slip this step
    double max_penetration = 0.0; ///< largest overlap (d)
    int n_self_contacts = 0;
    int n_wall_contacts = 0;
  };

  /// A force term (an effect) of the discrete model. add_forces() adds its
  /// forces to chain.f from the state at the start of the step and leaves
  /// its history untouched until commit(), so that it can be evaluated
  /// repeatedly (finite-difference tests).
  /// What a term adds to the explicit stability limit of a chain: to the
  /// bound on the squared highest frequency of its springs, and to the
  /// highest decay rate c/m of its dashpots (explicit_time_step).
  struct StabilityBound
  {
    double omega2 = 0.0;
    double rate = 0.0;
  };

  class Term
  {
  public:
    virtual ~Term() = default;
    virtual const char *name() const = 0;
    /// This term's share of the stability limit for nodes of `mass` spaced
    /// lambda0; ChainModel sums the shares of all its terms, in the order
    /// they were built. The default adds nothing: terms without springs or
    /// dashpots, and the clamp (ClampTerm), whose spring the cantilever's
    /// step has never counted.
    virtual StabilityBound stability_bound(double /*mass*/, double /*lambda0*/) const { return {}; }
    virtual void add_forces(Chain &chain, double dt, StepEnergy &energy) = 0;
    virtual void commit() {}
    /// Writes / reads the committed history (checkpoints); binary, same build.
    virtual void save(std::ostream &) const {}
    virtual void load(std::istream &) {}
  };
} // namespace wirefem::discrete
