// The two models' sections: Discrete and FEM (declare, parse, validate side
// by side).
#include "declarations.h"

#include <cmath>

namespace wirefem::scene
{
  void DiscreteParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Discrete/Segment length", "1", any_double, "lambda_0 (d): rest length of a spring.");
    d.declare("Discrete/Time step", "0", any_double,
              "Explicit time step. 0: Time step factor * the stability limit of the stiffest term.");
    d.declare("Discrete/Time step factor", "0.25", any_double,
              "Fraction of the estimated stability limit 2/omega_max used when Time step = 0.");
    d.declare("Discrete/Translational damping", "0", any_double,
              "gamma (1/time): viscous force -gamma m v on every free node against the fixed frame. "
              "Off by default: it drags wire sliding along itself with a distributed axial load "
              "gamma rho A v that folds spans longer than (4 pi^2 EI/(gamma rho A v))^(1/3) near the "
              "inlets (36 d at gamma = 0.05, v = 1) - no such drag exists in the experiment. The "
              "internal axial and rotational dashpots damp the wire instead.");
    d.declare("Discrete/Rotational damping", "0.5", any_double,
              "c (force d time): viscous moment -c dzeta/dt at each rotational spring; damps the "
              "highest bending modes (period ~0.2) and leaves slow loop motion alone.");
    d.declare("Discrete/Axial damping", "3", any_double,
              "c_a (force time / d): dashpot parallel to each tensile spring, tension c_a dlambda/dt. "
              "Damps axial waves (about 10% of critical for the shortest one at the paper's values, "
              "c_a = 0.1 sqrt(k1 m)) that otherwise dominate the measured inlet force; no drag on "
              "rigid motion.");
  }

  void DiscreteParameters::parse(const Declarations &d)
  {
    segment_length = d.get_double("Discrete/Segment length");
    time_step = d.get_double("Discrete/Time step");
    time_step_factor = d.get_double("Discrete/Time step factor");
    translational_damping = d.get_double("Discrete/Translational damping");
    rotational_damping = d.get_double("Discrete/Rotational damping");
    axial_damping = d.get_double("Discrete/Axial damping");
  }

  void DiscreteParameters::validate(const std::string &w) const
  {
    check(time_step >= 0, w, "Discrete/Time step", "must not be negative");
    check(time_step_factor > 0 && time_step_factor < 1, w, "Discrete/Time step factor", "must be in (0, 1)");
    check(translational_damping >= 0, w, "Discrete/Translational damping", "must not be negative");
    check(axial_damping >= 0, w, "Discrete/Axial damping", "must not be negative");
    check(rotational_damping >= 0, w, "Discrete/Rotational damping", "must not be negative");
  }

  void FemParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("FEM/Formulation", "reissner", Patterns::Selection("reissner|kirchhoff"),
              "Rod theory: 'reissner' (shear-deformable, shear stiffness GA) or 'kirchhoff' (shear-rigid: "
              "the shear strain is held at zero by a penalty Kirchhoff penalty * EA).");
    d.declare("FEM/Degree", "1", Patterns::Integer(1, 3),
              "Polynomial degree p of x, y and theta on each element (1, 2 or 3). The stiffness is "
              "integrated with p Gauss points (reduced), which keeps thin rods free of locking.");
    d.declare("FEM/Element length", "1", any_double, "Rest length h (d) of an element.");
    d.declare("FEM/Shear stiffness", "-1", any_double,
              "GA (force) of the Reissner rod. Negative: 0.9 EA/(2 (1 + 0.3)), a round wire with "
              "Poisson ratio 0.3 and shear coefficient 0.9.");
    d.declare("FEM/Kirchhoff penalty", "1000", any_double,
              "Kirchhoff formulation: shear penalty as a multiple of EA.");
    d.declare("FEM/Integrator", "generalized-alpha",
              Patterns::Selection("generalized-alpha|quasi-static|explicit"),
              "'generalized-alpha': implicit dynamics, Newton with line search and adaptive step; "
              "'quasi-static': no inertia (equilibrium of elastic, viscous and contact forces); "
              "'explicit': central differences with a lumped mass matrix (for comparison).");
    d.declare("FEM/Spectral radius", "0.9", any_double,
              "rho_infinity in [0, 1] of generalized-alpha: 1 keeps every frequency (no numerical "
              "dissipation), smaller values damp the unresolved high frequencies.");
    d.declare("FEM/Time step", "0", any_double,
              "Implicit: the first and largest time step; the step halves when Newton fails and "
              "grows again when it converges easily. 0: 0.025 d / Injection/Speed, at most 0.025 "
              "(smaller steps need fewer Newton iterations: on prm/quick.prm 0.025 is both cheaper and "
              "more accurate than 0.05). "
              "Explicit: the step; 0: 0.5 of the estimated stability limit.");
    d.declare("FEM/Minimum time step", "1e-7", any_double,
              "Below this the implicit step is not cut further: the run stops with a message.");
    d.declare("FEM/Newton tolerance", "1e-8", any_double,
              "Newton converges when the residual norm is below this times the force scale "
              "(EA + the largest inertial force) or the update below it times d.");
    d.declare("FEM/Friction law", "regularised", Patterns::Selection("regularised|spring"),
              "regularised: mu(v) tanh(v/v_th), smooth, creeps below v_th (the injection scenes). "
              "spring: the discrete model's law (a tangential spring capped at mu_st F_n while "
              "sticking, mu_d F_n while sliding), with a sharp slip onset; Set-up = capstan only.");
    d.declare("FEM/Maximum iterations", "15", Patterns::Integer(2, 200),
              "Newton iterations before the step is cut.");
    d.declare("FEM/Axial viscosity", "-1", any_double,
              "eta_a (force time): axial dashpot, N_v = eta_a d(eps)/dt. Negative: the discrete model's "
              "axial dashpot in its continuum limit, Discrete/Axial damping * Discrete/Segment length.");
    d.declare("FEM/Bending viscosity", "-1", any_double,
              "eta_b (force d^2 time): bending dashpot, M_v = eta_b d(kappa)/dt. Negative: "
              "Discrete/Rotational damping * Discrete/Segment length.");
  }

  void FemParameters::parse(const Declarations &d, const double axial_stiffness,
                            const DiscreteParameters &discrete)
  {
    formulation = d.get("FEM/Formulation") == "kirchhoff" ? Formulation::kirchhoff : Formulation::reissner;
    degree = static_cast<unsigned int>(std::stoul(d.get("FEM/Degree")));
    element_length = d.get_double("FEM/Element length");
    shear_stiffness = d.get_double("FEM/Shear stiffness");
    if (shear_stiffness < 0)
      shear_stiffness = 0.9 * axial_stiffness / 2.6;
    kirchhoff_penalty = d.get_double("FEM/Kirchhoff penalty");
    const auto name = d.get("FEM/Integrator");
    integrator = name == "explicit"       ? Integrator::explicit_lumped
                 : name == "quasi-static" ? Integrator::quasi_static
                                          : Integrator::generalized_alpha;
    spectral_radius = d.get_double("FEM/Spectral radius");
    time_step = d.get_double("FEM/Time step");
    minimum_time_step = d.get_double("FEM/Minimum time step");
    newton_tolerance = d.get_double("FEM/Newton tolerance");
    maximum_iterations = static_cast<unsigned int>(std::stoul(d.get("FEM/Maximum iterations")));
    spring_friction = d.get("FEM/Friction law") == "spring";
    axial_viscosity = d.get_double("FEM/Axial viscosity");
    if (axial_viscosity < 0)
      axial_viscosity = discrete.axial_damping * discrete.segment_length;
    bending_viscosity = d.get_double("FEM/Bending viscosity");
    if (bending_viscosity < 0)
      bending_viscosity = discrete.rotational_damping * discrete.segment_length;
  }

  void FemParameters::validate(const std::string &w) const
  {
    check(shear_stiffness > 0, w, "FEM/Shear stiffness", "must be positive");
    check(kirchhoff_penalty > 0, w, "FEM/Kirchhoff penalty", "must be positive");
    check(spectral_radius >= 0 && spectral_radius <= 1, w, "FEM/Spectral radius", "must be in [0, 1]");
    check(time_step >= 0, w, "FEM/Time step", "must not be negative");
    check(minimum_time_step > 0, w, "FEM/Minimum time step", "must be positive");
    check(newton_tolerance > 0, w, "FEM/Newton tolerance", "must be positive");
  }
} // namespace wirefem::scene
