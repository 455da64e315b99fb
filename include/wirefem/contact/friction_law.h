// Regularised Coulomb friction with static and dynamic coefficients and a
// threshold velocity, for one contact in the plane (the tangent is 1D).
//
// While a contact sticks, static friction is carried by a tangential spring
// k_t whose elongation u is the tangential displacement since the contact
// stuck; the force is -k_t u as long as |k_t u| <= mu_st F_N. Beyond that the
// contact slides with the dynamic force -mu_d F_N sign(v_t) against the
// relative tangential velocity v_t, and it sticks again once |v_t| < v_th.
// Sign convention: v_t is the velocity of side A relative to side B along the
// contact tangent t; the returned force acts on A along t (B gets minus it).
#pragma once

namespace wirefem::contact
{
  struct FrictionCoefficients
  {
    double mu_static = 0.0;
    double mu_dynamic = 0.0;
    double threshold_velocity = 0.0; ///< v_th (d / time)
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
  };

  /// One explicit update over a time step dt.
  inline FrictionResult friction_update(const FrictionCoefficients &c,
                                        const double normal_force,
                                        const double v_t,
                                        const double dt,
                                        const FrictionHistory &old)
  {
    FrictionResult r;
    if (old.sliding && (v_t >= c.threshold_velocity || -v_t >= c.threshold_velocity))
      {
        r.force = (v_t > 0.0 ? -1.0 : 1.0) * c.mu_dynamic * normal_force;
        r.history.sliding = true;
        r.history.elongation = -r.force / c.tangential_stiffness;
        return r;
      }
    r.history.sliding = false;
    r.history.elongation = old.elongation + v_t * dt;
    r.force = -c.tangential_stiffness * r.history.elongation;
    const double limit = c.mu_static * normal_force;
    if (r.force > limit || -r.force > limit)
      {
        r.force = (r.force > 0.0 ? 1.0 : -1.0) * c.mu_dynamic * normal_force;
        r.history.sliding = true;
        r.history.elongation = -r.force / c.tangential_stiffness;
      }
    return r;
  }
} // namespace wirefem::contact
