// The bilinear elastoplastic moment-curvature law, shared by the discrete
// model (strain = turning angle zeta, stiffness k2) and the FEM (strain =
// curvature kappa, stiffness EI).
//
//   M = c (e - e_p)                      elastic stiffness c
//   |M - X| <= M_y + R                   yield condition, M_y = c * e_y
//   kinematic: X = H e_p, R = 0          (yield range translates; default)
//   isotropic: X = 0,     R = H alpha    (yield range grows; alpha = int |de_p|)
//   H = s c / (1 - s)  so that the post-yield tangent is c H/(c + H) = s c.
//
// s = 1 gives an elastic law (H infinite); s = 0 perfect plasticity.
// Integration is the exact backward-Euler return mapping of this linear law;
// the algorithmic tangent equals the continuum one (c or s c).
#pragma once

namespace wirefem::material
{
  enum class Hardening
  {
    kinematic,
    isotropic
  };

  /// History of one rotational spring / quadrature point.
  struct PlasticState
  {
    double plastic_strain = 0.0;     ///< e_p (angle or curvature)
    double accumulated_strain = 0.0; ///< alpha = int |de_p| (isotropic hardening)
  };

  struct MomentResult
  {
    double moment = 0.0;       ///< M
    double tangent = 0.0;      ///< dM/de (algorithmic)
    PlasticState state;        ///< updated history
    double plastic_work = 0.0; ///< integral of M de_p over the increment (exact for the linear law)
  };

  class MomentCurvatureLaw
  {
  public:
    /// Elastic law with stiffness c.
    explicit MomentCurvatureLaw(double stiffness);
    /// Elastoplastic law: yield strain e_y (moment c e_y), hardening slope s.
    MomentCurvatureLaw(double stiffness, double yield_strain, double hardening_slope, Hardening hardening);

    MomentResult evaluate(double strain, const PlasticState &old_state) const;

    /// Elastic energy 1/2 c (e - e_p)^2 stored at this strain.
    double elastic_energy(double strain, const PlasticState &state) const
    {
      const double ee = strain - state.plastic_strain;
      return 0.5 * stiffness * ee * ee;
    }

    bool is_plastic() const { return plastic; }
    double elastic_stiffness() const { return stiffness; }

  private:
    double stiffness;
    double yield_moment = 0.0;
    double hardening_modulus = 0.0;
    Hardening hardening = Hardening::kinematic;
    bool plastic = false;
  };
} // namespace wirefem::material
