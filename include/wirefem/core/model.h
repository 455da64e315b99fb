// What the run loop needs from a wire model. Both the discrete chain and the
// rod FEM implement it, so the run loop, analysis and output never know which
// model they drive. The core module (this header, the wire state, the
// geometry and the binary I/O) includes no model and nothing above it.
#pragma once

#include <wirefem/core/wire_state.h>

#include <array>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wirefem::core
{
  /// Energies of the whole run (force * d). Potentials are current values,
  /// dissipations and the injection work are accumulated since the start.
  struct EnergyLedger
  {
    double stretching = 0.0;
    double shear = 0.0; ///< FEM: shear strain energy (0 in the discrete model)
    double bending = 0.0;
    double contact = 0.0;         ///< penalty energy of the normal contact springs
    double kinetic = 0.0;         ///< free wire
    double plastic = 0.0;         ///< plastic work
    double friction = 0.0;        ///< dissipated by friction
    double friction_stored = 0.0; ///< in sticking springs now (discrete model)
    double damping = 0.0;
    double injection_work = 0.0; ///< work of the channels plus kinetic energy of entering wire
    double initial = 0.0;        ///< stored in the perturbed initial wire at t = 0

    double stored() const { return stretching + shear + bending + contact + friction_stored + kinetic; }
    double dissipated() const { return plastic + friction + damping; }
    /// Energy in: the initial energy and the injection work.
    double in() const { return initial + injection_work; }
    /// What the ledger leaves out: energy in - stored - dissipated.
    double imbalance() const { return in() - stored() - dissipated(); }
    /// imbalance / energy in.
    double balance_error() const { return in() > 0.0 ? imbalance() / in() : 0.0; }
  };

  /// What the last step saw.
  struct StepReport
  {
    double max_penetration = 0.0; ///< largest contact overlap (d)
    int n_self_contacts = 0;
    int n_wall_contacts = 0;
  };

  /// A static equilibrium under a loading scaled by a load factor (Set-up =
  /// cantilever: the rod clamped at one end and loaded at the other).
  struct Equilibrium
  {
    bool converged = false;
    double residual = 0.0;           ///< largest free nodal force / the loading's force scale
    double tip_x = 0.0, tip_y = 0.0; ///< the loaded end (d)
    double tip_rotation = 0.0;       ///< direction angle of the rod at the loaded end
    std::vector<double> S, x, y;     ///< nodes from the clamp to the loaded end
  };

  /// What a capstan loading shows (Set-up = capstan: a wire on the wall
  /// over a wrap angle, pushed along it against a compressive end force).
  struct CapstanState
  {
    double wrap_angle = 0.0;           ///< angle the frictional contacts cover (rad)
    double pushed = 0.0;               ///< distance the trailing end was pushed (d)
    double push_force = 0.0;           ///< axial force at the pushed end (compression positive)
    double lead_slide = 0.0;           ///< arc distance the leading end moved (clockwise positive, d)
    double trailing_compression = 0.0; ///< at the first segment (quadrature point)
    double max_penetration = 0.0;      ///< largest wall overlap / d
    /// Angle from the leading end, compression: per segment (quadrature point).
    std::vector<std::array<double, 2>> profile;
  };

  class Model
  {
  public:
    virtual ~Model() = default;
    /// "discrete" or "fem".
    virtual std::string name() const = 0;
    /// One line on the discretisation (time step, elements, ...).
    virtual std::string description() const = 0;

    /// Advances by one time step; throws std::runtime_error with a message
    /// naming the limit when the model cannot continue.
    virtual void step() = 0;

    virtual double time() const = 0;
    virtual double time_step() const = 0;
    virtual unsigned long n_steps() const = 0;
    /// Wire length inside the cavity, L = 2 r + 2 u(t) (exact).
    virtual double injected_length() const = 0;
    /// Axial force with which each channel pushes (positive: the wire resists).
    virtual double force_left() const = 0;
    virtual double force_right() const = 0;
    virtual const EnergyLedger &energies() const = 0;
    virtual StepReport report() const = 0;
    /// Names of the effects this run simulates.
    virtual const std::vector<std::string> &active_effects() const = 0;
    /// Whether every coordinate and velocity is finite.
    virtual bool finite() const = 0;
    /// The wire from the left inlet to the right inlet, with per-point fields.
    virtual core::WireState wire_state() const = 0;

    /// Brings the wire from its current state to static equilibrium under
    /// the loading scaled by load_factor, each model by its own solver
    /// (loadings with a load factor only; the others throw).
    virtual Equilibrium equilibrate(double /*load_factor*/)
    {
      throw std::logic_error("this loading has no load factor");
    }
    /// The capstan loading's observables at the current time (the others throw).
    virtual CapstanState capstan_state() const { throw std::logic_error("this loading is not a capstan"); }
    /// Model-specific figures of the run for summary.json (name, value).
    virtual std::vector<std::pair<std::string, double>> statistics() const { return {}; }

    /// Writes the whole dynamic state so that a model built from the same
    /// scene continues bit for bit after load().
    virtual void save(std::ostream &out) const = 0;
    /// Throws std::runtime_error if the data do not fit this model.
    virtual void load(std::istream &in) = 0;

    /// Where the time went (written to the run log at the end); may be empty.
    virtual void print_timing(std::ostream &) const {}
  };
} // namespace wirefem::core
