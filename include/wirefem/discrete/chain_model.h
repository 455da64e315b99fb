// The discrete spring model of the paper, injected from two channels: builds
// the terms (effects) a scene calls for, integrates the equations of motion
// explicitly (semi-implicit Euler), feeds new nodes in at the inlets, and
// keeps the energy ledger.
#pragma once

#include <wirefem/core/wire_state.h>
#include <wirefem/discrete/chain.h>
#include <wirefem/injection/channels.h>
#include <wirefem/injection/inlet.h>
#include <wirefem/scene/parameters.h>
#include <wirefem/core/model.h>

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

  using core::EnergyLedger;

  class ChainModel final : public core::Model
  {
  public:
    explicit ChainModel(const scene::Scene &scene);
    ~ChainModel() override;

    std::string name() const override { return "discrete"; }
    std::string description() const override;

    /// One explicit time step.
    void step() override;

    double time() const override { return t; }
    double time_step() const override { return dt; }
    unsigned long n_steps() const override { return steps; }
    double injected_length() const override { return channels.injected_length(t); }
    /// Axial force with which each channel pushes (positive: wire resists),
    /// as the channel's work per injected length over the last lambda_0
    /// injected: a node passes the inlet once per lambda_0, so this window
    /// removes the step of the discrete moving boundary exactly.
    double force_left() const override { return window[0].mean(); }
    double force_right() const override { return window[1].mean(); }
    /// The instantaneous axial reaction of each channel's nodes.
    double instantaneous_force(int side) const { return inlet_force[side]; }
    const EnergyLedger &energies() const override { return ledger; }
    const StepEnergy &last_step() const { return step_energy; }
    core::StepReport report() const override
    {
      return {step_energy.max_penetration, step_energy.n_self_contacts, step_energy.n_wall_contacts};
    }
    /// Names of the effects this run simulates.
    const std::vector<std::string> &active_effects() const override { return effects; }
    const Chain &chain() const { return nodes; }
    /// Whether every coordinate and velocity is finite.
    bool finite() const override;

    /// The wire from the left inlet to the right inlet, with per-point fields.
    core::WireState wire_state() const override;

    /// Writes the whole dynamic state (chain, histories, ledger) so that a
    /// model built from the same scene continues bit for bit after load().
    void save(std::ostream &out) const override;
    /// Throws std::runtime_error if the data do not fit this model.
    void load(std::istream &in) override;

  private:
    void place_initial_wire(const scene::Scene &scene);
    void feed_channels();

    double radius, diameter, lambda0, k2;
    double hold = 0.0; ///< depth in the channels beyond which the wire is pushed
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

    using ForceWindow = injection::ForceWindow;
    ForceWindow window[2];
    EnergyLedger ledger;
    StepEnergy step_energy;
  };
} // namespace wirefem::discrete
