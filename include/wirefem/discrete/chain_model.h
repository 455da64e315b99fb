// The discrete spring model of the paper, injected from two channels (or,
// with Set-up = cantilever, clamped at one end and loaded at the other): builds
// the terms (effects) a scene calls for, integrates the equations of motion
// explicitly (semi-implicit Euler), feeds new nodes in at the inlets, and
// keeps the energy ledger.
#pragma once

#include <wirefem/core/wire_state.h>
#include <wirefem/discrete/chain.h>
#include <wirefem/injection/channel_placement.h>
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
  class EndLoadTerm;
  class EndThrustTerm;
  class SelfContactTerm;

  using core::EnergyLedger;

  class ChainModel final : public core::Model
  {
  public:
    explicit ChainModel(const scene::ChainScene &scene);
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

    /// Set-up = cantilever: dynamic relaxation to the equilibrium at
    /// load_factor. The load ramps linearly from the current factor over
    /// Cantilever/Load time / Points per leg; explicit steps with a
    /// mass-proportional drag (critical for the first mode unless
    /// Cantilever/Damping is set) run until the largest free nodal force is
    /// below Cantilever/Tolerance of the force scale.
    core::Equilibrium equilibrate(double load_factor) override;
    /// Set-up = capstan: the chain on the wall, its pushed end moved along
    /// it (velocity control) or pushed by a rising force (force control).
    core::CapstanState capstan_state() const override;
    std::vector<std::pair<std::string, double>> statistics() const override;

    /// Writes the whole dynamic state (chain, histories, ledger) so that a
    /// model built from the same scene continues bit for bit after load().
    void save(std::ostream &out) const override;
    /// Throws std::runtime_error if the data do not fit this model.
    void load(std::istream &in) override;

  private:
    void build_injected(const scene::ChainScene &scene);
    /// Storage for every node the injection can hold, the initial wire and
    /// the channels' nodes.
    void allocate_injected_chain(const scene::ChainScene &scene);
    /// Stretching, bending and damping.
    void add_material_terms(const scene::ChainScene &scene);
    /// Wall, self contact (with the curvature limit) and channel walls.
    void add_contact_terms(const scene::ChainScene &scene);
    /// Discrete/Time step, or Time step factor of the stability limit that
    /// the terms built so far report (Term::stability_bound): one place for
    /// every loading.
    double stable_time_step(const scene::DiscreteParameters &dd) const;
    void build_clamped(const scene::ChainScene &scene);
    void build_capstan(const scene::ChainScene &scene);
    /// One explicit step of the capstan loading.
    void capstan_step();
    /// Velocity control: nodes 0 and 1 where the push has taken them at t.
    void place_pushed_nodes();
    /// The clamp loading's forces at the current load factor; returns the
    /// largest free nodal force.
    double clamped_forces();
    /// One explicit step of the clamp loading with the forces of
    /// clamped_forces() (semi-implicit Euler, the drag at the step's midpoint).
    void clamped_advance();
    void place_initial_wire(const scene::ChainScene &scene);
    void feed_channels();

    double radius, diameter, lambda0, k2;
    double hold = 0.0; ///< depth in the channels beyond which the wire is pushed
    injection::Channels channels;
    /// A cavity other than the paper's circle, or channels off its x axis
    /// (scene::general_wall): its wall, shared with the wall contact term.
    std::shared_ptr<const injection::ChannelledWall> shaped_wall;
    Chain nodes;
    std::vector<std::unique_ptr<Term>> terms;
    BendingTerm *bending = nullptr;
    SelfContactTerm *self_contact = nullptr;
    /// The clamp loading (Set-up = cantilever).
    bool clamped = false;
    EndLoadTerm *end_load = nullptr;
    scene::CantileverParameters cantilever;
    double load_factor = 0.0, drag = 0.0, force_scale = 1.0;
    /// The capstan loading (Set-up = capstan).
    bool capstan_loading = false;
    scene::CapstanParameters capstan;
    struct CapstanState
    {
      double Rc = 0.0, zeta = 0.0, mu_static = 0.0, mu_dynamic = 0.0;
      int frictional = 0, first_free = 0;
      std::vector<core::Vec2> x0;
      EndThrustTerm *lead = nullptr, *push = nullptr;
      double roller_r = 0.0, roller_vr = 0.0;
    } cap;
    double stretching_stiffness = 0.0; ///< k1
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
