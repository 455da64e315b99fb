// The Cavity and Wire sections (declare, parse, validate side by side).
#include "declarations.h"

#include <cmath>

namespace wirefem::scene
{
  void CavityParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Cavity/Radius", "10", any_double,
              "Cavity radius r in units of the wire diameter d, i.e. f = r/d. Must be > 1.");
  }

  void CavityParameters::parse(const Declarations &d)
  {
    radius = d.get_double("Cavity/Radius");
  }

  void CavityParameters::validate(const std::string &w) const
  {
    check(radius > 1.0, w, "Cavity/Radius", "must be larger than 1 (the wire diameter)");
  }

  void WireParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    const auto boolean = Patterns::Bool();
    d.declare("Wire/Axial stiffness", "1000", any_double,
              "EA (force). The discrete model uses k1 = EA/lambda_0.");
    d.declare("Wire/Bending stiffness", "60", any_double,
              "EI (force d^2). The discrete model uses k2 = EI/lambda_0.");
    d.declare("Wire/Mass per length", "1", any_double, "rho A (mass per unit length d).");
    d.declare("Wire/Plasticity/Enabled", "true", boolean,
              "Elastoplastic bending. The wire is elastic anyway when Yield curvature * lambda_0 >= pi.");
    d.declare("Wire/Plasticity/Yield curvature", "0.04", any_double,
              "kappa_theta (1/d): yield moment EI*kappa_theta; alpha_theta = kappa_theta*lambda_0. "
              "Paper: 0 ... 0.06; pi/lambda_0 is elastic.");
    d.declare("Wire/Plasticity/Hardening slope", "0.05", any_double,
              "s in [0, 1]: post-yield slope s*EI of the moment-curvature law; unloading with slope EI.");
    d.declare("Wire/Plasticity/Hardening", "kinematic", Patterns::Selection("kinematic|isotropic"),
              "Linear kinematic (default: the yield range of width 2 M_y translates) or linear "
              "isotropic (the yield range grows). The paper does not say which.");
  }

  void WireParameters::parse(const Declarations &d)
  {
    axial_stiffness = d.get_double("Wire/Axial stiffness");
    bending_stiffness = d.get_double("Wire/Bending stiffness");
    mass_per_length = d.get_double("Wire/Mass per length");
    auto &pl = plasticity;
    pl.enabled = d.get_bool("Wire/Plasticity/Enabled");
    pl.yield_curvature = d.get_double("Wire/Plasticity/Yield curvature");
    pl.hardening_slope = d.get_double("Wire/Plasticity/Hardening slope");
    pl.hardening =
        d.get("Wire/Plasticity/Hardening") == "isotropic" ? Hardening::isotropic : Hardening::kinematic;
  }

  void WireParameters::validate(const std::string &w) const
  {
    check(axial_stiffness > 0, w, "Wire/Axial stiffness", "must be positive");
    check(bending_stiffness >= 0, w, "Wire/Bending stiffness", "must not be negative");
    check(mass_per_length > 0, w, "Wire/Mass per length", "must be positive");
    const auto &pl = plasticity;
    check(pl.yield_curvature >= 0, w, "Wire/Plasticity/Yield curvature", "must not be negative");
    check(pl.hardening_slope >= 0 && pl.hardening_slope <= 1, w, "Wire/Plasticity/Hardening slope",
          "must be in [0, 1]");
  }
} // namespace wirefem::scene
