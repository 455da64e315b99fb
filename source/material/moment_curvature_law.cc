#include <wirefem/material/moment_curvature_law.h>

#include <cmath>
#include <stdexcept>

namespace wirefem::material
{
  MomentCurvatureLaw::MomentCurvatureLaw(const double stiffness)
    : stiffness(stiffness)
  {
  }

  MomentCurvatureLaw::MomentCurvatureLaw(const double stiffness, const double yield_strain,
                                         const double hardening_slope, const Hardening hardening)
    : stiffness(stiffness)
    , yield_moment(stiffness * yield_strain)
    , hardening(hardening)
  {
    if (hardening_slope < 0.0 || hardening_slope > 1.0 || yield_strain < 0.0)
      throw std::invalid_argument("MomentCurvatureLaw: need 0 <= s <= 1 and yield strain >= 0");
    // s = 1 means the post-yield slope equals the elastic one: no plastic
    // flow at all, and H would be infinite.
    plastic = hardening_slope < 1.0;
    if (plastic)
      hardening_modulus = hardening_slope * stiffness / (1.0 - hardening_slope);
  }

  MomentResult MomentCurvatureLaw::evaluate(const double strain, const PlasticState &old) const
  {
    MomentResult r;
    r.state = old;
    const double trial = stiffness * (strain - old.plastic_strain);
    if (!plastic)
      {
        r.moment = trial;
        r.tangent = stiffness;
        return r;
      }
    const bool kinematic = hardening == Hardening::kinematic;
    const double back = kinematic ? hardening_modulus * old.plastic_strain : 0.0;
    const double radius = yield_moment + (kinematic ? 0.0 : hardening_modulus * old.accumulated_strain);
    const double xi = trial - back;
    const double f = std::abs(xi) - radius;
    if (f <= 0.0)
      {
        r.moment = trial;
        r.tangent = stiffness;
        return r;
      }
    // Linear hardening: the consistency condition is linear in the plastic
    // multiplier, so the return is exact in one step.
    const double dgamma = f / (stiffness + hardening_modulus);
    const double sign = xi > 0.0 ? 1.0 : -1.0;
    r.state.plastic_strain = old.plastic_strain + sign * dgamma;
    r.state.accumulated_strain = old.accumulated_strain + dgamma;
    r.moment = trial - stiffness * sign * dgamma;
    r.tangent = stiffness * hardening_modulus / (stiffness + hardening_modulus);
    // Work into plastic flow, integral of M de_p over the increment: during
    // flow M rises with e_p at the slope H, so the integral is M_new de_p
    // - H de_p^2 / 2 exactly (M_new de_p alone overstates it by H de_p^2/2
    // per increment, which does not cancel over a closed cycle).
    r.plastic_work = r.moment * sign * dgamma - 0.5 * hardening_modulus * dgamma * dgamma;
    return r;
  }
} // namespace wirefem::material
