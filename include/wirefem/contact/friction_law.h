// Regularised Coulomb friction with static and dynamic coefficients and a
// threshold velocity, for one contact in the plane (the tangent is 1D).
//
// Friction is carried by a tangential spring k_t whose elongation u grows
// with the relative tangential displacement of the contact points. The spring
// force -k_t u is capped: at mu_st F_N while the contact sticks; once that is
// exceeded the contact slides and the cap drops to mu_d F_N; it sticks again
// (cap mu_st F_N) once the relative tangential speed falls below v_th. When
// the cap is hit, the spring is shortened to the cap (the slip); the work the
// friction force took from the wire and the spring did not store is dissipated. Capping the spring rather
// than applying -mu_d F_N sign(v_t) keeps sliding free of chatter in an explicit scheme. Sign convention: v_t
// is the velocity of side A relative to side B along the contact tangent t; the returned force acts on A
// along t (B gets minus it).
#pragma once

#include <cmath>

namespace wirefem::contact
{
  struct FrictionCoefficients
  {
    double mu_static = 0.0;
    double mu_dynamic = 0.0;
    double threshold_velocity = 0.0;   ///< v_th (d / time)
    double tangential_stiffness = 0.0; ///< k_t (force / d)
  };

  /// History carried by a persistent contact pair.
  struct FrictionHistory
  {
    double elongation = 0.0; ///< u of the sticking spring (d)
    bool sliding = false;
  };

  struct FrictionResult
  {
    double force = 0.0; ///< tangential force on side A along t
    FrictionHistory history;
    double dissipated = 0.0; ///< work taken from the wire minus the change of spring energy
  };

  /// One explicit update over a time step dt.
  inline FrictionResult friction_update(const FrictionCoefficients &c, const double normal_force,
                                        const double v_t, const double dt, const FrictionHistory &old)
  {
    FrictionResult r;
    const bool keeps_sliding = old.sliding && (v_t >= c.threshold_velocity || -v_t >= c.threshold_velocity);
    const double limit = (keeps_sliding ? c.mu_dynamic : c.mu_static) * normal_force;
    const double trial = old.elongation + v_t * dt;
    r.force = -c.tangential_stiffness * trial;
    r.history.elongation = trial;
    r.history.sliding = false;
    if (r.force > limit || -r.force > limit)
      {
        r.force = (r.force > 0.0 ? 1.0 : -1.0) * c.mu_dynamic * normal_force;
        r.history.elongation = -r.force / c.tangential_stiffness;
        r.history.sliding = true;
      }
    // Energy: over the relative displacement v_t dt that brought the contact
    // here the friction force went from -k_t u_old to the new force; with
    // the central-difference scheme the kinetic energy changes by the work
    // of the mean of the two (trapezoidal rule), so that is the work taken
    // from the wire. What the spring did not store is dissipated: zero while
    // the contact sticks, whatever the step.
    const double k = c.tangential_stiffness;
    r.dissipated = 0.5 * (k * old.elongation - r.force) * v_t * dt -
                   0.5 * k * (r.history.elongation * r.history.elongation - old.elongation * old.elongation);
    return r;
  }
} // namespace wirefem::contact
