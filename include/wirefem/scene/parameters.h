// The scene: every parameter of a wirefem run, one struct per prm subsection.
//
// Units: the wire diameter d is the length unit; forces are in the unit in
// which EA and EI are given (paper: EA = 1000, EI = 60 at d = 1); time is in
// the unit implied by the mass per length (paper: 1). See --print-parameters
// for every key with its default and documentation.
#pragma once

#include <wirefem/material/moment_curvature_law.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace wirefem::scene
{
  // Each section below has a key table (source/scene/keys/*.json:
  // every key once, with its default, documentation, member and range);
  // `validate` checks what a range cannot say, and `resolve` turns the
  // negative "derive me" defaults into values (source/scene/section_checks.cc).
  // scene_reader.cc checks the combinations.

  enum class ModelType
  {
    discrete,
    fem
  };

  using material::Hardening;

  /// What the run does: the paper's injection into the cavity, or a
  /// benchmark set-up of validation/ (a rod clamped at one end and loaded at
  /// the other, in free space).
  enum class Setup
  {
    injection,
    cantilever,
    capstan
  };

  /// Set-up = cantilever: a straight rod of length L along +x, clamped at the
  /// origin (position and tangent), loaded at its free end by a dead force
  /// and a moment, both ramped linearly from zero over the load time; the
  /// run relaxes to static equilibrium (discrete model: dynamic relaxation
  /// with mass-proportional damping).
  struct CantileverParameters
  {
    double length = 20.0;     ///< L (d)
    double end_force_x = 0.0; ///< dead end force (force)
    double end_force_y = 0.0;
    double end_moment = 0.0;  ///< end moment (force d), + = counter-clockwise
    double load_time = 100.0; ///< ramp of the load over each leg of the history (time)
    /// Load factors the load passes through, linearly from 0 and from one to
    /// the next (a cyclic history: 1, -1, 1); the last one is the final load.
    std::vector<double> load_history{1.0};
    unsigned int points_per_leg = 1; ///< equilibria recorded along each leg (history.csv)

    /// The force scale of the equilibrium tolerance: EI/L^2 + |F| + |M|/L.
    double force_scale(const double bending_stiffness) const
    {
      return bending_stiffness / (length * length) + std::hypot(end_force_x, end_force_y) +
             std::abs(end_moment) / length;
    }
    double damping = 0.0;        ///< gamma of -gamma m v; 0: critical for the first mode
    double tolerance = 1e-10;    ///< largest nodal force / force scale at equilibrium
    double maximum_time = 1.0e6; ///< give up (exit 3) when not in equilibrium by then

    void validate(const std::string &where) const;
  };

  /// The load factors at which a cantilever run records an equilibrium, in
  /// order: points_per_leg evenly spaced ones along each leg of the history.
  inline std::vector<double> load_points(const CantileverParameters &cl)
  {
    std::vector<double> points;
    double previous = 0.0;
    for (const double f : cl.load_history)
      {
        for (unsigned int j = 1; j <= cl.points_per_leg; ++j)
          points.push_back(previous + (f - previous) * j / cl.points_per_leg);
        previous = f;
      }
    return points;
  }

  /// Set-up = capstan: a wire lying on the cavity wall over a wrap angle,
  /// centred on the top of the cavity, pushed clockwise along the wall
  /// against a compressive follower force T0 on its leading end (validation
  /// case 5, the capstan law). Both ends carry the moment that holds the
  /// wire at the wall's curvature, so the wire has no bending boundary layer.
  struct CapstanParameters
  {
    double wrap_angle = 1.5707963267948966; ///< angle the frictional part of the wire covers (rad)
    double end_force = 1.0;                 ///< T0, compressive, on the leading end (force)
    /// 'velocity': the trailing end (two nodes) slides
    /// along the wall at Speed, and the push force of steady sliding is
    /// measured; 'force': a compressive follower force on the trailing end
    /// rises at Force rate until the wire slips (the stick/slip threshold).
    bool velocity_control = true;
    double speed = 0.05;         ///< push speed (d / time), above the threshold velocity
    double ramp_time = 50.0;     ///< the end loads and the speed rise linearly from 0 over this time
    double slide = 10.0;         ///< velocity control: distance pushed (d)
    double force_rate = 1e-3;    ///< force control: d(push force)/dt in units of T0 per time
    double slip_distance = 0.01; ///< force control: slipped once the leading end moved this far (d)
    /// velocity control: the pushed end's radius is free (true) or held
    bool trailing_roller = true;
    double maximum_time = 1.0e6;

    /// Velocity control: the push speed at time t, rising linearly over the
    /// ramp time.
    double push_speed(const double t) const { return t < ramp_time ? speed * t / ramp_time : speed; }
    /// Velocity control: the distance pushed by time t.
    double pushed(const double t) const
    {
      return t < ramp_time ? 0.5 * speed * t * t / ramp_time : speed * (t - 0.5 * ramp_time);
    }
    /// The end force T0 at time t: it rises linearly over the ramp time.
    double end_force_at(const double t) const { return end_force * (t < ramp_time ? t / ramp_time : 1.0); }
    /// Force control: the push at time t, rising with the end force over the
    /// ramp and then at Force rate.
    double push_force_at(const double t) const
    {
      const double ramp = t < ramp_time ? t / ramp_time : 1.0;
      return end_force * (ramp + force_rate * std::max(0.0, t - ramp_time));
    }
    /// Velocity control: the time by which Slide has been pushed.
    double slide_time() const
    {
      return slide >= 0.5 * speed * ramp_time ? slide / speed + 0.5 * ramp_time
                                              : std::sqrt(2.0 * slide * ramp_time / speed);
    }

    void validate(const std::string &where) const;
  };

  enum class CavityShape
  {
    circle,
    ellipse,
    polygon
  };

  /// The cavity. Every shape has the area pi r^2 of the circle of radius r,
  /// so that phi = d L/(pi r^2) and f = r/d mean the same for all of them.
  struct CavityParameters
  {
    double radius = 10.0; ///< r in units of d (f = r/d)
    CavityShape shape = CavityShape::circle;
    double aspect_ratio = 1.5;                                ///< ellipse: a/b >= 1, a along x
    std::vector<double> vertices{-1, -1, 1, -1, 1, 1, -1, 1}; ///< polygon: x, y pairs
    std::string vertex_file;                                  ///< polygon: read the vertices from it
    double corner_radius = 2.0;                               ///< polygon: rounded corners (d)

    void validate(const std::string &where) const;
  };

  struct PlasticityParameters
  {
    bool enabled = true;
    double yield_curvature = 0.04; ///< kappa_theta (1/d)
    double hardening_slope = 0.05; ///< s in [0,1]: post-yield slope s*EI
    Hardening hardening = Hardening::kinematic;
  };

  struct WireParameters
  {
    double axial_stiffness = 1000.0; ///< EA (force)
    double bending_stiffness = 60.0; ///< EI (force d^2)
    double mass_per_length = 1.0;    ///< rho A (mass / d)
    PlasticityParameters plasticity;
  };

  struct FrictionParameters
  {
    double static_coefficient = 0.0;         ///< mu_st, wire-wire
    double dynamic_coefficient = 0.0;        ///< mu_d <= mu_st, wire-wire
    double wall_static_coefficient = 0.0;    ///< mu_st at the wall
    double wall_dynamic_coefficient = 0.0;   ///< mu_d at the wall
    double threshold_velocity = 0.01;        ///< v_th (d / time): below it, static again
    double tangential_stiffness_ratio = 0.2; ///< k_t / k_n of the sticking spring
    bool surface_torque = false;             ///< friction acts at the surface (arm d/2), discrete model
  };

  struct ContactParameters
  {
    bool wall_contact = true;
    bool self_contact = true;
    double normal_stiffness = 2000.0; ///< k_n (force / d), penalty
    double skin = 0.5;                ///< Verlet skin of the candidate list (d)
    double exclusion_length = 3.0;    ///< arc length (d) within which segments never touch
    FrictionParameters friction;

    /// Negative friction coefficients become the ones they derive from.
    void resolve();
    void validate(const std::string &where) const;
  };

  struct InjectionParameters
  {
    double speed = 1.0;               ///< injection speed of each channel (d / time)
    double ramp_time = 10.0;          ///< time over which the speed rises smoothly from 0
    double slow_start_speed = 0.0;    ///< speed (d / time) of the slow start
    double slow_start_length = 0.0;   ///< length (d) each channel pushes at it; 0: no slow start
    unsigned int seed = 1;            ///< seed of the symmetry-breaking perturbation
    double perturbation = 0.5;        ///< amplitude of the initial transverse perturbation (d)
    double mirror_asymmetry = 1.0;    ///< scale of its modes antisymmetric about the mid-plane (0: symmetric)
    bool tangential_channels = false; ///< channels along the wall instead of radial
    /// Where the channels meet the wall: fractions of the wall's length
    /// from its start, counter-clockwise; the left channel's, then the right's.
    std::vector<double> channel_positions{0.5, 0.0};
    double channel_angle = 0.0;           ///< degrees between each channel and the wall's inward normal
    double maximum_packing_density = 0.6; ///< stop at this phi even if not jammed
    double jamming_force = 50.0;          ///< jammed when the mean inlet force exceeds this (force)
    double jamming_window = 1.0;          ///< injected length over which the force is averaged (d)
    double maximum_time = std::numeric_limits<double>::infinity(); ///< stop at this time

    /// radius: the initial wire sets the smallest packing density.
    void validate(const std::string &where, double radius) const;
  };

  struct DiscreteParameters
  {
    double segment_length = 1.0; ///< lambda_0 (d)
    double time_step = 0.0;      ///< 0: automatic, time_step_factor * stability limit
    double time_step_factor = 0.25;
    double translational_damping = 0.0; ///< gamma: damping force -gamma m v (1 / time)
    double rotational_damping = 0.5;    ///< c: damping moment -c dzeta/dt (force d time)
    double axial_damping = 3.0;         ///< c_a: dashpot tension c_a dlambda/dt (force time / d)
  };

  enum class Formulation
  {
    reissner, ///< shear-deformable Simo-Reissner rod
    kirchhoff ///< shear-rigid: shear strain held at zero by a penalty
  };

  enum class Integrator
  {
    generalized_alpha, ///< implicit dynamics, Newton with line search, adaptive step
    quasi_static,      ///< no inertia: equilibrium (with the viscous dashpots) at each step
    explicit_lumped    ///< central differences with a lumped mass matrix
  };

  /// FEM/Self friction law.
  enum class SelfFrictionLaw
  {
    automatic,   ///< spring with generalized-alpha and contact at the nodes, else regularised
    regularised, ///< mu(v) tanh(v / v_th) on every node-segment pair
    spring       ///< the discrete model's tangential springs
  };

  /// FEM/Linear solver.
  enum class LinearSolver
  {
    refactorise,  ///< a sparse LU of every tangent
    kept_factors, ///< GMRES preconditioned by the LU of an earlier tangent
    band,         ///< GMRES preconditioned by the LU of the tangent's band
    automatic     ///< the band with generalized-alpha, an LU elsewhere and with modified Newton
  };

  struct FemParameters
  {
    Formulation formulation = Formulation::reissner;
    unsigned int degree = 1;           ///< polynomial degree p of (x, y, theta), 1..3
    double element_length = 1.0;       ///< rest length h of an element (d)
    double shear_stiffness = -1.0;     ///< GA (force); < 0: 0.9 EA / (2 (1 + 0.3)), a round steel wire
    double kirchhoff_penalty = 1000.0; ///< Kirchhoff: shear penalty GA_K = this * EA
    Integrator integrator = Integrator::generalized_alpha;
    double spectral_radius = 0.9; ///< rho_infinity of generalized-alpha
    double time_step = 0.0;       ///< first (and largest) step; 0: automatic
    double minimum_time_step = 1e-7;
    double newton_tolerance = 0.0; ///< on the residual norm relative to the force scale; 0: by the integrator
    unsigned int maximum_iterations = 15;
    bool velocity_predictor = true;  ///< Newton starts from u + h v, not u + h v + h^2 a / 2
    double overlap_growth = 0.0;     ///< d per step before a converged step is cut; 0: off
    double step_error = 0.01;        ///< d: local error a step may make (0: off)
    double step_energy_error = 0.03; ///< with step_error: energy error of two steps / their energy in
    LinearSolver linear_solver = LinearSolver::automatic;
    double linear_tolerance = 0.0;      ///< GMRES's, relative to the Newton residual; 0: by the solver
    double linear_floor = 1e-3;         ///< GMRES's, relative to the Newton tolerance
    unsigned int krylov_iterations = 0; ///< GMRES iterations before an LU; 0: by the solver
    bool modified_newton = false;       ///< reuse a step's first LU while Newton contracts fast
    double newton_contraction = 0.1;    ///< modified Newton: largest residual ratio on kept factors
    bool spring_friction = true;        ///< wall friction by the discrete model's law (FEM/Friction law)
    SelfFrictionLaw self_friction_law = SelfFrictionLaw::automatic;
    bool spring_self_friction = false; ///< self friction by the discrete model's law (resolved)
    /// Contact (wall and self): 0, at the nodes; n > 0, at n Gauss points
    /// of each segment of the wire along its element.
    unsigned int contact_points = 0;
    /// Wire-wire contact: its penalty as a multiple of Contact/Normal
    /// stiffness per side (1: two wires meet at k_n per length; 2: at the
    /// chain's 2 k_n).
    double self_contact_stiffness = 1.0;
    /// eta_a (force time): axial dashpot N_v = eta_a d(eps)/dt; from the
    /// scene file, or the discrete model's dashpot in its continuum limit
    /// (Discrete/Axial damping * lambda_0) when that is negative.
    double axial_viscosity = -1.0;
    /// eta_b (force d^2 time): bending dashpot M_v = eta_b d(kappa)/dt;
    /// likewise from Discrete/Rotational damping * lambda_0 when negative.
    double bending_viscosity = -1.0;
    /// gamma (1/time): drag -gamma m v on the free nodes' positions (m the
    /// lumped nodal mass), as Discrete/Translational damping; with inertia.
    double translational_damping = 0.0;
    /// Quasi-static injection: the dashpots act in its quasi-static steps
    /// (rates over the injection's time), not only in its dynamic phases.
    bool quasi_static_dashpots = true;
    /// Quasi-static injection: friction's creep per injected length (its
    /// regularised law's slip scale over a step's injection); 0: v_th over
    /// the injection speed (the dynamic law's, speed-dependent).
    double quasi_static_creep = 0.03;
    /// Quasi-static injection: a step whose own imbalance is over four times
    /// this fraction of its share of the energy put in is made again, shorter.
    double quasi_static_energy_error = 0.1;

    /// The defaults that come from other sections or keys: the shear
    /// stiffness from EA, the dashpots from the discrete model's, the self
    /// friction law from the integrator and the contact points, GMRES's
    /// tolerance and iterations from the linear solver.
    void resolve(double axial_stiffness, const DiscreteParameters &discrete);
  };

  struct OutputParameters
  {
    std::string directory;              ///< empty: output/<scene name>
    double interval = 1.0;              ///< injected length between rows of series.csv (d)
    double vtu_interval = 20.0;         ///< injected length between VTU files (d); 0: none
    int picture_size = 1000;            ///< pixels
    std::string progress = "auto";      ///< auto | on | off
    double checkpoint_interval = 300.0; ///< wall seconds between checkpoints; 0: only on interruption
  };

  /// Yield angle alpha_theta = kappa_theta * lambda_0 of the discrete model.
  inline double yield_angle(const WireParameters &wire, const DiscreteParameters &discrete)
  {
    return wire.plasticity.yield_curvature * discrete.segment_length;
  }

  /// The sections both models read: the set-up with its loading, the
  /// cavity, the wire and the contacts.
  struct PhysicsSections
  {
    Setup setup = Setup::injection;
    CantileverParameters cantilever;
    CapstanParameters capstan;
    CavityParameters cavity;
    WireParameters wire;
    ContactParameters contact;
    InjectionParameters injection;
    bool keep_neutral_effects = false; ///< build effects even with neutral parameters
  };

  struct Scene : PhysicsSections
  {
    std::string name;     ///< prm file stem
    std::string prm_file; ///< as given on the command line
    ModelType model = ModelType::discrete;
    DiscreteParameters discrete;
    FemParameters fem;
    OutputParameters output;
    /// Every key outside Output with its value, one "Section/Key = value"
    /// line each, sorted by key (read_scene): a checkpoint resumes only the
    /// scene with the same fingerprint.
    std::string fingerprint;

    /// Whether bending is elastoplastic: plasticity enabled on a wire with
    /// bending stiffness, and not neutral (a yield angle below pi and a
    /// hardening slope below 1), unless neutral effects are kept. Both
    /// models decide by this.
    bool plastic_bending() const
    {
      const auto &pl = wire.plasticity;
      return wire.bending_stiffness > 0.0 && pl.enabled &&
             (keep_neutral_effects ||
              (scene::yield_angle(wire, discrete) < M_PI && pl.hardening_slope < 1.0));
    }
  };

  /// What a model reads of a scene: the shared sections and the decisions
  /// both models take alike; not the output, not the other model's
  /// numerics. The factory (simulation::make_model) hands each model its
  /// own view.
  struct PhysicsScene : PhysicsSections
  {
    bool plastic_bending = false; ///< Scene::plastic_bending()

    explicit PhysicsScene(const Scene &s)
      : PhysicsSections(s)
      , plastic_bending(s.plastic_bending())
    {
    }
  };

  /// The discrete model's view of a scene.
  struct ChainScene : PhysicsScene
  {
    DiscreteParameters discrete;

    ChainScene(const Scene &s) // NOLINT: a Scene is handed to the model as its view
      : PhysicsScene(s)
      , discrete(s.discrete)
    {
    }
    double yield_angle() const { return scene::yield_angle(wire, discrete); }
  };

  /// The rod FEM's view of a scene.
  struct RodScene : PhysicsScene
  {
    FemParameters fem;

    RodScene(const Scene &s) // NOLINT: a Scene is handed to the model as its view
      : PhysicsScene(s)
      , fem(s.fem)
    {
    }
  };
} // namespace wirefem::scene
