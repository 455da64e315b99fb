// The force terms of the discrete model, one per effect. Each is built only
// when the scene calls for its effect and owns exactly the state it needs.
#pragma once

#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/friction_law.h>
#include <wirefem/discrete/chain.h>
#include <wirefem/geometry/cavity.h>
#include <wirefem/injection/channel_placement.h>
#include <wirefem/injection/channels.h>
#include <wirefem/core/binary.h>
#include <wirefem/material/moment_curvature_law.h>

#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace wirefem::discrete
{
  /// The dissipative force of the previous step, per node or segment, for
  /// the energy ledger: the central-difference scheme changes the kinetic
  /// energy by the work of the mean of two successive forces (trapezoidal
  /// rule), so a dashpot dissipates c (rate_{n-1} + rate_n)/2 rate_n dt, not
  /// c rate_n^2 dt; the difference grows with every step of a chattering
  /// packing. Index k becomes active once and stays active, so a new entry
  /// starts from a zero force.
  template <typename T>
  struct PreviousRates
  {
    std::vector<T> committed, trial;
    void resize(const int capacity)
    {
      committed.assign(capacity, T{});
      trial.assign(capacity, T{});
    }
    bool empty() const { return committed.empty(); }
    void commit() { committed.swap(trial); }
    /// Checkpoints: the committed values (nothing when empty).
    void save(std::ostream &out) const
    {
      if (!empty())
        core::write_vector(out, committed, 0, committed.size());
    }
    void load(std::istream &in)
    {
      if (empty())
        return;
      core::read_vector(in, committed);
      trial = committed;
    }
  };

  /// The friction share of the energy ledger of a contact term, from the
  /// work its nodal forces do. A contact's friction force is spread over the
  /// nodes of its segments with the weights of the current closest points
  /// and acts along the current tangent; both move between steps, so the
  /// work the scheme lets those nodal forces do (trapezoidal rule, as for the
  /// dashpots) is not exactly the work the contact's tangential spring sees
  /// (in a jammed frictional packing the difference reached 0.3% of the
  /// injection work). Friction dissipates minus the nodal work minus the
  /// change of the energy stored in the sticking springs; a spring released
  /// when its contact opens thereby dissipates its energy.
  class FrictionWork
  {
  public:
    void resize(const int capacity) { force.resize(capacity); }
    /// Starts an evaluation: clears the nodal friction forces of the active nodes.
    void begin(const Chain &c);
    void add_force(const int k, const core::Vec2 &f) { force.trial[k] += f; }
    void add_stored(const double energy) { stored_trial += energy; }
    /// Dissipated over the step that brought the chain to its positions
    /// (x_n - x_{n-1} = v dt: velocities are at the half step).
    double dissipated(const Chain &c, double dt) const;
    void commit()
    {
      force.commit();
      stored = stored_trial;
    }
    void save(std::ostream &out) const;
    void load(std::istream &in);

  private:
    PreviousRates<core::Vec2> force; // nodal friction force, previous step and now
    double stored = 0.0, stored_trial = 0.0;
  };

  /// Tensile springs F = -k1 (lambda_0 - lambda) on every active segment,
  /// with an optional dashpot c_a d(lambda)/dt in parallel (internal: it
  /// damps axial waves and leaves rigid sliding of the wire alone).
  class StretchingTerm : public Term
  {
  public:
    /// capacity: number of nodes of the chain (needed with a dashpot).
    explicit StretchingTerm(double k1, double axial_damping = 0.0, int capacity = 0);
    const char *name() const override { return "stretching"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;

  private:
    double k1;
    double damping;
    PreviousRates<double> previous; // dashpot rate per segment
  };

  /// Rotational springs M = -k2 (zeta - zeta_p) at every interior active
  /// node, zeta the signed turning angle (+ = left) between the neighbouring
  /// segments. With a plastic law, zeta_p evolves by its return mapping (state
  /// only allocated then). An optional dashpot adds -c dzeta/dt.
  class BendingTerm : public Term
  {
  public:
    BendingTerm(const material::MomentCurvatureLaw &law, double rotational_damping, int capacity);
    const char *name() const override { return "bending"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;

    /// Turning angle at node k (needs k-1, k+1 active).
    static double turning_angle(const Chain &chain, int k);
    double plastic_angle(int k) const { return state.empty() ? 0.0 : state[k].plastic_strain; }
    bool has_plasticity() const { return !state.empty(); }

  private:
    material::MomentCurvatureLaw law;
    double damping;
    std::vector<material::PlasticState> state;       // committed, per node
    std::vector<material::PlasticState> trial_state; // from the last add_forces
    PreviousRates<double> previous;                  // dashpot rate per node
  };

  /// The excluded volume of the wire at the scale of one node: a wire of
  /// diameter d cannot bend to a radius below d/2, i.e. |zeta| <= zeta_max =
  /// 2 lambda_0/d (capped at 2 pi/3, where the next-nearest nodes would touch).
  /// Beyond it a penalty moment k (|zeta| - zeta_max) acts, with k = k_n
  /// lambda_0^3 / 4 from the contact penalty (force k_n lambda_0 overlap at an
  /// arm of lambda_0). Part of the self-contact effect: segments closer along
  /// the wire than the exclusion length are otherwise free to cross.
  class CurvatureLimitTerm : public Term
  {
  public:
    CurvatureLimitTerm(double zeta_max, double stiffness)
      : zeta_max(zeta_max)
      , stiffness(stiffness)
    {
    }
    const char *name() const override { return "curvature limit"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;

  private:
    double zeta_max;
    double stiffness;
  };

  /// Viscous force -gamma m v on every free node.
  class DampingTerm : public Term
  {
  public:
    DampingTerm(double gamma, int capacity);
    const char *name() const override { return "damping"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;

  private:
    double gamma;
    PreviousRates<core::Vec2> previous; // velocity per node
  };

  /// The moment of a rotational spring at turning angle zeta: the return
  /// mapping of `old` into `trial` when the law is plastic (state pointers
  /// unused otherwise); books the elastic energy and the plastic work.
  double spring_moment(const material::MomentCurvatureLaw &law, double zeta,
                       const material::PlasticState *old, material::PlasticState *trial, StepEnergy &energy);

  /// The clamp of a cantilever (Set-up = cantilever): the first active node
  /// is held in place and the first segment's direction is held along
  /// `direction` by a rotational spring. That spring stands for the half
  /// segment of wire next to the clamp, so its stiffness is 2 k2 and its
  /// yield angle alpha/2 (the same yield moment): the turning angle zeta_0
  /// between the clamp direction and the first segment then approximates the
  /// curvature at the clamp as zeta_0 = kappa lambda_0/2, and the chain's
  /// segment directions are the continuum's at the segment midpoints, which
  /// keeps the discretisation second order. Its energy is booked as bending.
  class ClampTerm : public Term
  {
  public:
    /// law: the interior nodes' law (stiffness k2, yield angle alpha).
    ClampTerm(const material::MomentCurvatureLaw &clamp_law, core::Vec2 direction);
    const char *name() const override { return "clamp"; }
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override { state = trial_state; }
    /// zeta_0 at the current state.
    double angle(const Chain &chain) const;

  private:
    material::MomentCurvatureLaw law;
    core::Vec2 direction;
    material::PlasticState state, trial_state;
  };

  /// A dead force and a moment on the free end of a cantilever (the last
  /// active node and the last segment), scaled by a load factor. Potential
  /// V = -factor (F . x_N + M phi) (booked as load_potential), phi the
  /// direction angle of the last segment, followed continuously through full
  /// turns (unwrapped against the committed angle).
  class EndLoadTerm : public Term
  {
  public:
    EndLoadTerm(core::Vec2 force, double moment);
    const char *name() const override { return "end load"; }
    void set_load_factor(double f) { factor = f; }
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override { committed_angle = trial_angle; }
    /// Unwrapped direction angle of the last segment.
    double end_angle(const Chain &chain) const;
    /// V at the current state.
    double potential(const Chain &chain) const;

  private:
    core::Vec2 force;
    double moment;
    double factor = 1.0;
    double committed_angle = 0.0, trial_angle = 0.0;
  };

  /// A compressive follower force and a moment on one end of the chain
  /// (Set-up = capstan). The end node is pushed along its segment towards
  /// the wire's interior by `thrust`: a follower load, which turns with the
  /// segment and has no potential. The end segment carries the moment
  /// `moment` (counter-clockwise positive; potential -M phi, phi the
  /// segment's direction angle), booked as load_potential for small turns.
  class EndThrustTerm : public Term
  {
  public:
    enum class End
    {
      first,
      last
    };
    EndThrustTerm(End end, double thrust, double moment);
    const char *name() const override { return "end thrust"; }
    void set_thrust(double t) { thrust = t; }
    double get_thrust() const { return thrust; }
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;

  private:
    End end;
    double thrust;
    double moment;
  };

  /// A nodal force, for the moments of surface friction.
  struct NodalForce
  {
    int node = 0;
    core::Vec2 force;
  };

  /// Angular velocity of segment a -> a + 1.
  double segment_rotation_rate(const Chain &chain, int a);
  /// Rotation rate of node k: the mean of its segments' angular velocities
  /// (its one segment's at an end of the active chain).
  double node_rotation_rate(const Chain &chain, int k);
  /// The nodal forces of a moment M on segment a -> a + 1 (2 entries) or on
  /// node k (up to 4), work-conjugate to the rates above: the sum of
  /// force . v over the entries is M times the rate. Return the count.
  int segment_moment_forces(const Chain &chain, int a, double moment, NodalForce *out);
  int node_moment_forces(const Chain &chain, int k, double moment, NodalForce *out);

  /// Parameters shared by the contact terms.
  struct ContactLaw
  {
    double diameter = 1.0;
    double normal_stiffness = 1000.0;
    bool friction = false;
    contact::FrictionCoefficients coefficients;
    /// Friction acts at the surface, d/2 off the centreline: it turns the
    /// wire there too, and the slip includes the surface's turning.
    bool surface_torque = false;
  };

  /// Any cavity with channels anywhere on its wall (scene::general_wall).
  using ShapedWall = injection::ChannelledWall;

  /// Wire-wall contact: the node's surface stays off the wall, the circle of
  /// radius r with an opening of width d at each channel. A node whose polar
  /// angle lies within an opening meets the opening's nearest corner (the
  /// wall's end at y = +-d/2), so the distance to the wall, and the force, is
  /// continuous as a node moves across the mouth. With a ShapedWall the same
  /// holds for any cavity: a node whose nearest wall point lies in a mouth,
  /// or that is in a channel behind its mouth, meets the mouth's nearest
  /// corner.
  class WallContactTerm : public Term
  {
  public:
    /// capacity: number of nodes of the chain (needed with friction).
    WallContactTerm(double radius, const ContactLaw &law, int capacity = 0);
    /// The wall of any cavity instead of the circle of radius r.
    void use_shaped_wall(std::shared_ptr<const ShapedWall> wall) { shaped = std::move(wall); }
    /// The channels are tangential (injection/channels.h): the wall is a
    /// whole circle, without the radial mouths, and the wire still in a
    /// channel (the end nodes behind its inlet) is left to the channel walls.
    void make_channels_tangential() { tangential = true; }
    const char *name() const override { return "wall contact"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;

  private:
    double radius;
    ContactLaw law;
    bool tangential = false;
    std::shared_ptr<const ShapedWall> shaped;
    /// The circle's rule (above): whether the node at p overlaps the wall,
    /// by how much, and the unit vector towards it.
    bool touch_circle(const core::Vec2 &p, double half_d, double corner_x, double &overlap,
                      core::Vec2 &towards) const;
    bool touch_shaped(const core::Vec2 &p, double half_d, double &overlap, core::Vec2 &towards) const;
    std::unordered_map<int, contact::FrictionHistory> history, trial_history;
    FrictionWork friction_work;
  };

  /// The walls of the two channels, from their mouths at the inlets
  /// outwards: a zero-clearance guide that holds the wire on the channel
  /// axis by a distributed lateral spring of stiffness k_c per length,
  /// energy (k_c/2) times the integral of y^2 over the part of each segment
  /// inside a channel (s < 0, s the distance past the inlet along the axis,
  /// y the offset from it). The part inside shrinks continuously as a
  /// segment leaves through the mouth, so a node passing the inlet is let go
  /// gradually. Holding the innermost channel node rigidly on the axis
  /// until it passes the inlet instead releases, once per node, the moment
  /// that node carried: the wire's bending energy density at the inlet is
  /// lost on every segment length injected, a dissipation that does not
  /// vanish as lambda_0 -> 0 (it tripled the elastic spiral's injection
  /// force). A mouth rounded over one diameter (the stiffness rising from 0
  /// over that depth, integrated by Gauss points) lost nearly as much: the
  /// wire then rides over the mouth's corners, which act on nodes. The
  /// energy is booked as contact; |y| of the nodes inside counts as
  /// penetration.
  class ChannelTerm : public Term
  {
  public:
    /// channels: their mouths and axes; stiffness: k_c, force per length per
    /// unit lateral offset.
    ChannelTerm(const injection::Channels &channels, double stiffness)
      : channels(channels)
      , stiffness(stiffness)
    {
    }
    const char *name() const override { return "channel walls"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;

  private:
    /// Adds the segment (a, b)'s energy and forces for the channel of `side`;
    /// false when it lies wholly outside.
    bool add_segment(Chain &c, int a, int b, injection::Side side, StepEnergy &e) const;
    injection::Channels channels;
    double stiffness;
  };

  /// Wire-wire contact, node to segment both ways: each node against the
  /// segments of the wire nearby that are closer than d, with candidates from
  /// the broad phase (segment pairs). Of the segments of one stretch of wire
  /// only the nearest counts, so the energy is 1/2 k_n (d - r)^2 with r the
  /// node's distance to that stretch, continuous as nodes glide past each
  /// other's nodes. A node pressed on a wire is as stiff as on the wall (k_n
  /// the law's per-node penalty); two wires side by side meet node by node
  /// from both sides, twice that per length. Its friction history follows a
  /// node from segment to segment.
  class SelfContactTerm : public Term
  {
  public:
    /// exclusion: a node never touches a segment whose nearer node is at
    /// most this many nodes away along the wire; capacity: number of nodes
    /// of the chain (needed with friction).
    SelfContactTerm(const ContactLaw &law, double skin, int exclusion, int capacity = 0);
    const char *name() const override { return "self contact"; }
    StabilityBound stability_bound(double mass, double lambda0) const override;
    void add_forces(Chain &chain, double dt, StepEnergy &energy) override;
    void commit() override;
    void save(std::ostream &out) const override;
    void load(std::istream &in) override;

    struct ActivePair
    {
      int i, j;    ///< segments (i < j); a node is the start (or the chain's last node the end) of one
      double s, t; ///< closest-point parameters
      double normal_force;
    };
    const std::vector<ActivePair> &active_pairs() const { return active; }
    const contact::BroadPhase &broad_phase() const { return broad; }

  private:
    /// The friction force on node k in contact with segment m (at its
    /// parameter t, normal n, normal force fn), with the history, stored
    /// energy and work it books; the segment takes the opposite force.
    core::Vec2 friction_force(Chain &c, int k, int m, double t, core::Vec2 n, double fn, double dt,
                              StepEnergy &e);
    static std::uint64_t key(int i, int j)
    {
      return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) |
             static_cast<std::uint32_t>(j);
    }
    /// A contact's friction history (key: node, segment); `taken` marks that a current contact has
    /// inherited it this step, so it is handed on at most once.
    struct StoredHistory
    {
      contact::FrictionHistory history;
      bool taken = false;
    };
    ContactLaw law;
    int exclusion;
    contact::BroadPhase broad;
    std::vector<ActivePair> active;
    std::unordered_map<std::uint64_t, StoredHistory> history, trial_history;
    FrictionWork friction_work;
  };
} // namespace wirefem::discrete
