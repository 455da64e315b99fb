// The discrete spring model of the paper, injected from two channels: builds
// the terms (effects) a scene calls for, integrates the equations of motion
// explicitly (semi-implicit Euler), feeds new nodes in at the inlets, and
// keeps the energy ledger.
#pragma once

#include <wirefem/analysis/wire_state.h>
#include <wirefem/discrete/chain.h>
#include <wirefem/injection/channels.h>
#include <wirefem/scene/parameters.h>

#include <deque>
#include <iosfwd>
#include <utility>
#include <memory>
#include <string>
#include <vector>

namespace wirefem::discrete
{
  class BendingTerm;
  class SelfContactTerm;

  /// Energies of the whole run (force * d). Potentials are current values,
  /// dissipations and the injection work are accumulated since the start.
  struct EnergyLedger
  {
    double stretching = 0.0;
    double bending = 0.0;
    double contact = 0.0;         ///< penalty energy of the normal contact springs
    double kinetic = 0.0;         ///< free nodes
    double plastic = 0.0;         ///< plastic work
    double friction = 0.0;        ///< dissipated by slip of the friction springs
    double friction_stored = 0.0; ///< in sticking springs now
    double damping = 0.0;
    double injection_work = 0.0; ///< work of the channels plus kinetic energy of entering wire
    double initial = 0.0;        ///< stored in the perturbed initial wire at t = 0

    double stored() const { return stretching + bending + contact + friction_stored + kinetic; }
    double dissipated() const { return plastic + friction + damping; }
    /// (energy in - stored - dissipated) / energy in, energy in = initial + injection work.
    double balance_error() const
    {
      const double in = initial + injection_work;
      return in > 0.0 ? (in - stored() - dissipated()) / in : 0.0;
    }
  };

  class ChainModel
  {
  public:
    explicit ChainModel(const scene::Scene &scene);
    ~ChainModel();

    /// One explicit time step.
    void step();

    double time() const { return t; }
    double time_step() const { return dt; }
    unsigned long n_steps() const { return steps; }
    double injected_length() const { return channels.injected_length(t); }
    /// Axial force with which each channel pushes (positive: wire resists),
    /// as the channel's work per injected length over the last lambda_0
    /// injected: a node passes the inlet once per lambda_0, so this window
    /// removes the step of the discrete moving boundary exactly.
    double force_left() const { return window[0].mean(); }
    double force_right() const { return window[1].mean(); }
    /// The instantaneous axial reaction of each channel's nodes.
    double instantaneous_force(int side) const { return inlet_force[side]; }
    const EnergyLedger &energies() const { return ledger; }
    const StepEnergy &last_step() const { return step_energy; }
    /// Names of the effects this run simulates.
    const std::vector<std::string> &active_effects() const { return effects; }
    const Chain &chain() const { return nodes; }
    /// Whether every coordinate and velocity is finite.
    bool finite() const;

    /// The wire from the left inlet to the right inlet, with per-point fields.
    analysis::WireState wire_state() const;

    /// Writes the whole dynamic state (chain, histories, ledger) so that a
    /// model built from the same scene continues bit for bit after load().
    void save(std::ostream &out) const;
    /// Throws std::runtime_error if the data do not fit this model.
    void load(std::istream &in);

  private:
    void place_initial_wire(const scene::Scene &scene);
    void feed_channels();

    double radius, diameter, lambda0, k2;
    injection::Channels channels;
    Chain nodes;
    std::vector<std::unique_ptr<Term>> terms;
    BendingTerm *bending = nullptr;
    SelfContactTerm *self_contact = nullptr;
    std::vector<std::string> effects;
    int left_origin = 0;  // storage index of the node at the left inlet at t = 0
    int right_origin = 0; // same, right
    double t = 0.0, dt = 0.0;
    unsigned long steps = 0;
    double inlet_force[2] = {0.0, 0.0};

    /// Work of one channel over the last `length` of injection.
    struct ForceWindow
    {
      double length = 1.0;
      std::deque<std::pair<double, double>> steps; // (injected, work)
      double injected = 0.0, work = 0.0;
      void add(double du, double dw);
      double mean() const { return injected > 0.0 ? work / injected : 0.0; }
    };
    ForceWindow window[2];
    EnergyLedger ledger;
    StepEnergy step_energy;
  };
} // namespace wirefem::discrete
