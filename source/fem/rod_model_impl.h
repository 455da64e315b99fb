// The rod FEM's internals, shared by its source files (not installed):
// the evaluation of the residual, the assembly request, the end-of-step
// state of an implicit step, and RodModel::Impl.
#pragma once

#include <wirefem/analysis/observables.h>
#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/friction_law.h>
#include <wirefem/contact/segment_distance.h>
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/csr_matrix.h>
#include <wirefem/fem/pair_springs.h>
#include <wirefem/fem/rod_element.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/fem/sparse_direct.h>
#include <wirefem/injection/channels.h>
#include <wirefem/injection/inlet.h>
#include <wirefem/core/binary.h>
#include <wirefem/core/section_timer.h>
#include "pattern_slack.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/conditional_ostream.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <optional>
#include <cstdlib>
#include <iostream>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace wirefem::fem
{
  using core::Vec2;
  using injection::Side;

  /// Everything an evaluation of the residual produces.
  struct Evaluation
  {
    dealii::Vector<double> residual;    ///< full, all dofs (reactions at prescribed dofs)
    dealii::Vector<double> force;       ///< conservative internal + contact forces, full
    dealii::Vector<double> dissipative; ///< viscous + friction forces, full
    dealii::Vector<double> friction;    ///< friction forces, full
    std::vector<PointState> state;      ///< per cell and quadrature point
    std::vector<double> node_contact_force;
    struct Pair
    {
      int i, j;
      double s, t, fn;
    };
    std::vector<Pair> pairs;
    double axial = 0, shear = 0, bending = 0, contact = 0, plastic = 0, max_overlap = 0;
    double friction_damping = 0; ///< the largest friction_damping() under the regularised law
    int n_wall = 0;
    double push_force = 0;                              ///< capstan: axial force at the pushed end
    std::vector<contact::FrictionHistory> wall_history; ///< spring law: trial, per node
    std::vector<PairSpring> self_history;               ///< spring law: trial, per pair
    double friction_stored = 0;                         ///< spring law: in the wall springs
  };

  /// What one assembly is asked for: the state at the end of the step, the
  /// free range, and how the time integrator weights the parts.
  struct AssemblyRequest
  {
    const dealii::Vector<double> *u = nullptr;       ///< positions and angles
    const dealii::Vector<double> *a_blend = nullptr; ///< blended acceleration (inertia)
    const dealii::Vector<double> *v0 = nullptr;      ///< the velocity is c_vel u + v0
    double step = 0.0;                               ///< for the dashpot rates; 0: none
    double c_vel = 0.0;
    int first = 0, last = 0; ///< free nodes [first, last)
    bool want_tangent = false;
    double c_mass = 0.0;      ///< weight of the mass matrix in the tangent
    double c_force = 1.0;     ///< weight of the forces in the tangent
    double blend_force = 1.0; ///< weight of the conservative forces in the residual
    bool constrain = true;    ///< eliminate the capstan roller's tangential dof
    /// Friction sees the velocity times this: 1, or for quasi-static
    /// injection step / dt_max (FEM/Quasi-static creep: rod_stepper.cc), so
    /// its regularisation then acts on the slip of a step, whatever its length.
    double friction_rate = 1.0;

    /// The part of the velocity friction sees that does not depend on u,
    /// at node k, and its weight of u.
    core::Vec2 velocity0(const int k) const
    {
      return {friction_rate * (*v0)[3 * k], friction_rate * (*v0)[3 * k + 1]};
    }
    double friction_c_vel() const { return friction_rate * c_vel; }
    /// The time over which friction's rates are measured.
    double friction_step() const { return step / friction_rate; }
    /// Weight of the friction (dissipative) part of a contact tangent.
    double friction_scale() const { return c_force > 0 ? 1.0 / c_force : 1.0; }

    AssemblyRequest without_tangent() const
    {
      AssemblyRequest r = *this;
      r.want_tangent = false;
      return r;
    }
  };

  /// The end-of-step state of an implicit step as the Newton iteration
  /// moves u1: v1 = c_vel u1 + v0 and a1 = (u1 - u_hat) / (beta step^2)
  /// (zero without inertia), a_blend = (1 - alpha_m) a1 + alpha_m a_n.
  struct StepState
  {
    dealii::Vector<double> u1, v1, a1, v0, a_blend, u_hat;
    const dealii::Vector<double> *a_n = nullptr;
    double step = 0.0, c_vel = 0.0, beta = 0.25, alpha_m = 0.0;
    bool inertia = true;

    /// v1, a1 and a_blend from u1.
    void update()
    {
      for (unsigned int i = 0; i < u1.size(); ++i)
        {
          a1[i] = inertia ? (u1[i] - u_hat[i]) / (beta * step * step) : 0.0;
          v1[i] = c_vel * u1[i] + v0[i];
          a_blend[i] = (1.0 - alpha_m) * a1[i] + alpha_m * (*a_n)[i];
        }
    }
  };

  struct RodModel::Impl
  {
    scene::RodScene scene;
    double radius, diameter, rhoA, rhoI;
    injection::Channels channels;
    unsigned int p;
    double h;
    dealii::Triangulation<1, 2> tria;
    dealii::FESystem<1, 2> fe;
    dealii::DoFHandler<1, 2> dof_handler;
    ElementShape stiffness_shape, mass_shape;
    std::vector<double> element_mass; // 3n x 3n, same for every element
    SectionProperties section;
    material::MomentCurvatureLaw law{1.0};
    bool plastic = false, viscous = false;
    double drag = 0; ///< FEM/Translational damping gamma (1/time); 0: off
    ContactSettings wall_settings, self_settings;
    /// Wall (and self) friction by the discrete model's spring law (FEM/Friction
    /// law, FEM/Self friction law = spring): the springs of the last accepted step.
    bool wall_spring = false, self_spring = false;
    std::vector<contact::FrictionHistory> wall_springs;
    PairSprings self_springs;
    /// Where each node was when its wall spring was last committed: the
    /// start of the step for an implicit step, the start of the step
    /// before for an explicit one (whose forces are taken at the start).
    std::vector<Vec2> spring_from;
    void note_spring_positions(const dealii::Vector<double> &at);

    unsigned int n_cells = 0, n_nodes = 0, n_local = 0;
    std::vector<double> node_S;                       // material coordinate of node k (sorted)
    std::vector<std::vector<unsigned int>> cell_node; // node of local node a
    /// FEM/Contact points > 0: segment k's contact points, on its cell's curve.
    struct ContactPoint
    {
      unsigned int cell;
      double along, weight;      ///< where in the segment ([0, 1]); the wire length it stands for
      std::array<double, 4> N{}; ///< the cell's shape functions there
    };
    std::vector<std::vector<ContactPoint>> segment_points;
    void set_up_contact_points(unsigned int n_points);
    /// Kirchhoff: section angles of least elastic energy, positions held.
    void relax_section_angles();
    double a_left = 0, a_right = 0, min_spacing = 0; // a_*: material coordinates of the inlets at t = 0

    // Generalized-alpha.
    double alpha_m = 0, alpha_f = 0, beta = 0.25, gamma = 0.5;
    bool inertia = true;
    /// Integrator = quasi-static on the injection set-up: steps by injected
    /// length, a stress-free start shape, friction on slip per step.
    bool quasi_static_injection = false;
    /// Quasi-static injection hands a snap (a step Newton cannot take even cut below
    /// FEM/Minimum time step) to generalized-alpha with the injection paused, until the
    /// kinetic energy has fallen below qs_calm of the stored one for qs_calm_steps steps in
    /// a row. A snap that comes back where the last one was (within qs_again of injection,
    /// the default longest step) is a point quasi-static Newton cannot pass: that phase
    /// first injects qs_push of wire per channel at the scene's speed, then pauses.
    std::optional<double> pause_from; ///< time the injection was paused at, in a dynamic phase
    std::optional<double> push_to;    ///< wire per channel a pushing phase injects to
    double paused_total = 0.0;        ///< time spent paused before
    unsigned long calm_steps = 0, snaps = 0, dynamic_steps = 0, pushes = 0;
    double last_snap_at = -1.0;               ///< wire per channel at the last snap
    static constexpr double qs_push = 0.25;   ///< d
    static constexpr double qs_again = 0.025; ///< d: a snap this near the last one is where it was
    double qs_dt_max = 0, dynamic_dt_max = 0;
    static constexpr double qs_calm = 1e-3;
    static constexpr unsigned long qs_calm_steps = 10;
    /// Generalized-alpha's parameters of the dynamic phases.
    double dyn_alpha_m = 0, dyn_alpha_f = 0, dyn_beta = 0.25, dyn_gamma = 0.5;
    /// The channels' clock: time less the paused time.
    double injection_time(double time) const { return pause_from.value_or(time) - paused_total; }
    bool injecting() const { return !pause_from; }
    bool dynamic_phase() const { return pause_from.has_value() || push_to.has_value(); }
    bool quasi_static_step() const { return quasi_static_injection && !dynamic_phase(); } ///< not a snap
    /// Quasi-static injection: to generalized-alpha (injection paused, or pushing first), and back.
    void enter_dynamics();
    /// After a dynamic step: the end of a push, a calm wire.
    void after_dynamic_step();
    void leave_dynamics();
    /// The integrator's settings (inertia, generalized-alpha's parameters,
    /// the longest step) of a dynamic phase or of quasi-static stepping.
    void use_integrator(bool dynamic);
    /// The dynamic phase's state in the checkpoint (after the rest).
    void save_quasi_static(std::ostream &out) const;
    void load_quasi_static(std::istream &in);

    // State at t_n.
    dealii::Vector<double> u, v, a, f_old;
    /// Quasi-static steps: the dissipative and friction forces at t_n.
    dealii::Vector<double> dissipative_old, friction_old;
    std::vector<PointState> qp;
    double t = 0, dt = 0, dt_max = 0;
    unsigned long steps = 0, cuts = 0;
    /// FEM/Overlap growth (injection set-up; 0: off) and the steps cut for it;
    /// FEM/Step error and Step energy error (0: off), the last step's estimates,
    /// their larger ratio to them, the steps cut; the last step's imbalance, length.
    double overlap_growth = 0, step_error = 0, step_energy_error = 0;
    double error_estimate = 0, energy_estimate = 0, error_ratio = 0, last_imbalance = 0, last_step = 0;
    unsigned long overlap_cuts = 0, error_cuts = 0;
    unsigned long newton_iterations = 0; ///< linear solves of Newton's method in all
    int first_free = 0, last_free = 0;   // free nodes [first, last)
    /// The channels push the wire deeper than `hold` inside them (those nodes
    /// are prescribed); from there to the mouth the channel walls guide it
    /// (fem::channel_wall_element in evaluate()), so a node is let go gradually
    /// as it leaves.
    double hold = 0;
    double k_channel = 0; ///< lateral stiffness of the channel walls per length
    double wall_time = 0; ///< time at which evaluate() places the channel mouths

    contact::BroadPhase broad;
    int exclusion = 1;
    /// The tangent, in the sorted rows the LU reads (assembly adds into the values factorised).
    CsrMatrix K;
    /// Per cell, the position in K's values of each entry of its element matrix
    /// (n_local^2, row major; -1 outside the free range), found with the pattern.
    std::vector<int> cell_position;
    /// K's LU (KLU): analysed once per pattern, refactorised per iteration.
    SparseDirect lu;
    std::vector<double> lu_rhs, lu_solution; ///< solve_linear's scratch
    /// Solves K x = rhs; false when K is singular. With a tolerance > 0, by GMRES on the kept factors or
    /// the band's (SparseDirect::solve_kept, solve_band) to |rhs - K x|_2 <= tolerance; else an LU.
    bool solve_linear(const dealii::Vector<double> &rhs, dealii::Vector<double> &x, double tolerance = 0.0);
    bool factorise_K();
    /// FEM/Predictor = constant velocity: Newton starts from u + h v.
    bool velocity_predictor = false;
    /// FEM/Linear solver = kept factors, on the injection set-up (the clamp and capstan refactorise:
    /// small systems, and only a direct solve's exact last update keeps the slender cantilever's order).
    bool kept_factors = false;
    /// FEM/Linear solver = band or auto (as kept_factors).
    bool band_solver = false;
    /// Steps that failed with GMRES and were tried again with an LU each.
    unsigned long retried_steps = 0;
    /// FEM/Newton = modified, on the injection set-up: a step's LU is
    /// reused while Newton contracts by newton_contraction or better.
    bool modified_newton = false;
    double newton_contraction = 0.1;
    unsigned int step_tangents = 0; ///< tangents factorised in the last step
    /// Solves with the factors of the last factorise_K().
    bool solve_factorised(const dealii::Vector<double> &rhs, dealii::Vector<double> &x);
    /// K's pattern: the elements of the free range [sp_first, sp_last) and the contact pairs sp_pairs
    /// (sorted), the candidates within pattern_margin of contact when it was built; only these can touch
    /// until it is built again. The checkpoint holds it, so a resumed run rounds as one not resumed.
    int sp_first = -1, sp_last = -1;
    std::vector<contact::SegmentPair> sp_pairs;
    std::vector<std::vector<int>> sp_adjacent; ///< pattern_rows' scratch, kept for its capacity
    void pattern_rows(int first, int last, const std::vector<contact::SegmentPair> &pairs,
                      std::vector<int> &row_start, std::vector<int> &columns); ///< K's rows (CSR)
    double pattern_margin = 0;
    /// A pair's chord distance at `u` (its boxes' gap once that reaches cutoff); closer_than: below cutoff.
    double chord_gap(const dealii::Vector<double> &u, const contact::SegmentPair &pr, double cutoff) const;
    bool closer_than(const dealii::Vector<double> &u, const contact::SegmentPair &pr, double cutoff) const;
    /// The candidate pairs of positions `u` closer than diameter + reach.
    void near_pairs(const dealii::Vector<double> &u, double reach,
                    std::vector<contact::SegmentPair> &out) const;
    /// Whether every candidate pair at `u` closer than `reach` (all that can touch) is in K's pattern.
    bool pattern_covers(const dealii::Vector<double> &u, double reach);
    PatternSlack sp_slack;
    /// Chords closer than this can touch: d + 2 x the largest point-to-chord distance.
    double contact_reach(const dealii::Vector<double> &x, int first, int last) const;

    core::EnergyLedger ledger;
    core::StepReport last_report;
    injection::ForceWindow window[2];
    std::vector<std::string> effects;
    std::vector<double> history;
    Evaluation latest; ///< at the last accepted state
    core::SectionTimer timer;

    /// Set-up = cantilever: the clamp loading. Node 0 is held at the origin
    /// along +x; the end load of the scene, times load_factor, acts on the
    /// last node; no contact and no inertia. Each load increment is a
    /// quasi-static step of the same Newton solver (follow_load).
    bool clamped = false;
    double load_factor = 0.0;
    double newton_tolerance = 0.0; ///< absolute, on the max norm of the free residual
    double force_scale = 1.0;      ///< of the reported residual
    /// Backtracking in Newton's method. The clamp's load path takes full
    /// Newton steps: a rod rolled up by an end moment is reached by full
    /// steps whose max-norm residual first grows (stretching), and the path
    /// controls its increments itself.
    bool line_search = true;
    struct LoadPath
    {
      double increment = 0.1;
      bool was_stable = true;
      unsigned long increments = 0;
      unsigned int unstable_states_left = 0;
      double lowest_eigenvalue = 0.0;
      double residual = 0.0;
    } path;
    void assemble_end_load(Evaluation &e) const;
    /// The clamp loading's equilibrium at `goal`, reached by load increments
    /// from the current state (rod_load_path.cc).
    core::Equilibrium follow_load(double goal);
    /// One quasi-static Newton step at load factor `factor`; commits on success.
    bool static_step(double factor);
    /// The eigenvalue of smallest magnitude of K (assembled at the committed
    /// state) and its mode on the free dofs, by inverse iteration.
    double lowest_eigenvalue(dealii::Vector<double> &mode);
    /// What a rejected load increment restores.
    struct Committed
    {
      dealii::Vector<double> u, v, a, f_old;
      std::vector<PointState> qp;
      double t = 0.0, load_factor = 0.0;
      unsigned long steps = 0;
      core::EnergyLedger ledger;
    };
    Committed committed() const { return {u, v, a, f_old, qp, t, load_factor, steps, ledger}; }
    void restore(const Committed &c)
    {
      u = c.u;
      v = c.v;
      a = c.a;
      f_old = c.f_old;
      qp = c.qp;
      t = c.t;
      load_factor = c.load_factor;
      steps = c.steps;
      ledger = c.ledger;
    }

    /// Set-up = capstan (rod_capstan.cc): the rod on the wall's centreline circle over the
    /// wrap angle, running clockwise from its trailing end (node 0). The leading end carries
    /// a compressive follower force and the moment that holds the wall's curvature. Velocity
    /// control pushes the trailing end along the wall: its polar and section angles are
    /// prescribed, its radius free (a roller: its (x, y) rotated to (radial, tangential) and
    /// the tangential row and column eliminated) or held. Force control pushes it by a
    /// follower force instead. Quasi-static.
    bool capstan = false;
    struct CapstanLoading
    {
      double Rc = 0.0;          ///< radius of the centreline on the wall
      double a0 = 0.0;          ///< polar angle of the trailing end at t = 0
      double held = 0.0;        ///< the moment that holds the wall's curvature
      double lead_angle0 = 0.0; ///< polar angle of the leading end at t = 0
      double t_end = 0.0;       ///< velocity control: the time the slide is done
      bool velocity = true, roller = true;
    } cap;
    void build_capstan_mesh(const scene::RodScene &s);
    void set_capstan_state();
    /// Follower forces and end moments at the time of the step (wall_time).
    void assemble_capstan_loads(const AssemblyRequest &rq, Evaluation &e);
    /// The push force at the trailing end and, for the roller, its rotated
    /// radial dof (residual and, with the tangent, K); the tests compare
    /// the tangent before this (rq.constrain false).
    void constrain_trailing_end(const AssemblyRequest &rq, Evaluation &e);
    /// Newton's correction of the roller's radial dof back to (x, y).
    void expand_trailing_end(dealii::Vector<double> &dx) const;
    /// The capstan's predictor: the whole rod slid with the trailing end
    /// (velocity control), or the state itself (force control).
    void predict_capstan(double step, StepState &x) const;
    core::CapstanState capstan_state() const;

    /// After a converged but unstable increment from `start`: the state
    /// left along its lowest mode and solved again (at most four times);
    /// false when Newton fails even from the unstable state.
    bool leave_unstable_state(const Committed &start, double target, dealii::Vector<double> &mode);
    /// The clamp loading's current state as an equilibrium.
    core::Equilibrium equilibrium(bool converged) const;

    explicit Impl(const scene::RodScene &s);
    /// The mesh of the whole wire that can ever enter, numbered node by node
    /// along the wire; node coordinates and the element mass matrix.
    void build_mesh(const scene::RodScene &s);
    /// n_cells, h and the inlets' material coordinates of the injection.
    void build_channel_mesh(const scene::RodScene &s);
    /// The triangulation of n_cells elements of length h, its dofs and nodes.
    void make_mesh();
    /// Section, material, contact settings, the effects of the run, and the
    /// time integrator's parameters and step.
    void build_physics(const scene::RodScene &s);
    /// Section, moment-curvature law, dashpots.
    void build_material(const scene::RodScene &s);
    /// Wall and self contact settings, the broad phase.
    void build_contact(const scene::RodScene &s);
    /// Time integrator (or static path), Newton's tolerance and step.
    void build_integrator(const scene::RodScene &s);
    /// Quasi-static injection: relaxes the stretch of the start shape with
    /// the channels held, then opens the ledger.
    void relax_start();
    /// The longest implicit step of the injection set-up when FEM/Time step is 0.
    double default_step(const scene::RodScene &s) const;
    /// The longest generalized-alpha step of the injection set-up.
    double dynamic_step(const scene::RodScene &s) const;
    /// Generalized-alpha's parameters for FEM/Spectral radius, kept for
    /// the run and for the dynamic phases of quasi-static injection.
    void set_generalized_alpha(double rho);
    /// alpha_m, alpha_f, beta, gamma: generalized-alpha's, or the
    /// trapezoidal rule's (implicit Euler without inertia).
    void use_alpha(bool generalized);
    /// The seeded shape at rest, its initial acceleration and stored energy.
    void set_initial_state(const scene::RodScene &s);
    /// The injection's initial wire (across the cavity, the tangential S or
    /// the curve between channels anywhere), on the channel axes beyond.
    void place_injected_wire(const scene::RodScene &s), place_on_initial_curve(const scene::RodScene &s);
    int node_dof(unsigned int node, unsigned int c) const { return static_cast<int>(3 * node + c); }
    /// Wire pushed through each channel by this time.
    double injected_at(double time) const { return channels.injected_per_channel(injection_time(time)); }
    double left_inlet_S(double time) const { return a_left - injected_at(time); }
    double right_inlet_S(double t) const { return a_right + (channels.count() > 1 ? injected_at(t) : 0.0); }
    /// The nodes with material coordinate in (sl, sr); past(last): one more, within the mesh (a free end).
    void nodes_between(double sl, double sr, int &first, int &last) const;
    int past(int last) const { return std::min(last + 1, static_cast<int>(n_nodes)); }
    void free_range(double time, int &first, int &last) const;
    /// The nodes strictly between the inlets (material coordinate past them).
    void inside_range(double time, int &first, int &last) const;
    void prescribe(double time, dealii::Vector<double> &x, dealii::Vector<double> *vel,
                   dealii::Vector<double> *acc, int first, int last) const;
    Vec2 position(const dealii::Vector<double> &x, unsigned int k) const { return {x[3 * k], x[3 * k + 1]}; }
    double node_weight(unsigned int k) const
    {
      const double l = k > 0 ? node_S[k] - node_S[k - 1] : 0.0;
      const double r = k + 1 < n_nodes ? node_S[k + 1] - node_S[k] : 0.0;
      return 0.5 * (l + r);
    }

    /// Assembles what the request asks for into e; with want_tangent the matrix K (dofs of the free range)
    /// is filled. One function per contribution, each adding to e and K.
    void evaluate(const AssemblyRequest &rq, Evaluation &e);
    void assemble_elements(const AssemblyRequest &rq, Evaluation &e);
    void assemble_drag(const AssemblyRequest &rq, Evaluation &e); ///< FEM/Translational damping
    void assemble_wall(const AssemblyRequest &rq, Evaluation &e);
    /// The wall's spring law at wall site i (a node, or a contact point
    /// along the element) at position x standing for wire length `weight`.
    bool wall_spring_contact(const AssemblyRequest &rq, unsigned int i, const Vec2 &x, double weight,
                             ContactContribution &cc, Evaluation &e) const;
    void self_spring_friction(const AssemblyRequest &rq, int node, int seg, Evaluation &e);
    /// FEM/Contact points > 0: the wall at the points of segments [first, last).
    void assemble_wall_along(const AssemblyRequest &rq, int first, int last, Evaluation &e);
    Vec2 point_position(const dealii::Vector<double> &x, const ContactPoint &cp) const;
    Vec2 point_velocity0(const AssemblyRequest &rq, const ContactPoint &cp) const;
    /// The wall's sites: the nodes, or (FEM/Contact points > 0) the contact points.
    unsigned int n_wall_sites() const;
    void assemble_channel_walls(const AssemblyRequest &rq, Evaluation &e);
    void assemble_self_contact(const AssemblyRequest &rq, Evaluation &e);
    /// FEM/Contact points > 0: each candidate segment's points against the other's stretch.
    void assemble_self_contact_along(const AssemblyRequest &rq, Evaluation &e);
    /// Adds a contribution on a point of cell `cell` (shape functions N) and the
    /// nodes of segment seg (none when seg < 0, a wall contact), the point's
    /// force and tangent carried to the cell's nodes.
    void add_point_on_cell(const AssemblyRequest &rq, const ContactContribution &cc, unsigned int cell,
                           const std::array<double, 4> &N, int seg, Evaluation &e);
    /// Adds scale * m (the square matrix on the n global dofs g, row
    /// major) to K, restricted to the free range; each dof is component
    /// g % 3 of node g / 3.
    void add_matrix(const AssemblyRequest &rq, const int *g, int n, const double *m, double scale);
    /// Adds a contact contribution on the nodes listed (x and y of each).
    void add_contact(const AssemblyRequest &rq, const ContactContribution &cc,
                     std::initializer_list<int> nodes, Evaluation &e);
    /// Adds a contact's residual (and its friction part) on the dofs g.
    void add_contact_forces(const AssemblyRequest &rq, const int *g, int n, const double *residual,
                            const double *friction, Evaluation &e);
    /// K's pattern for the free range [first, last) and these contact pairs.
    void rebuild_sparsity(int first, int last, std::vector<contact::SegmentPair> pairs);
    /// How an implicit step ended: committed, Newton failed, converged
    /// to a state whose largest overlap grew by more than FEM/Overlap
    /// growth, converged to a state with a contact its candidates missed,
    /// or converged with a local error above FEM/Step error (none but the
    /// first committed).
    enum class StepOutcome
    {
      converged,
      not_converged,
      overlap_grew,
      missed_contact,
      error_too_large
    };
    /// Whether Newton's iteration saw every contact of x: the candidates
    /// (updated at the step's start) cover x, or, rebuilt at x, list no
    /// pair in contact they did not list before. A quasi-static step can
    /// jump to a far equilibrium, past the skin, with one wire through
    /// another.
    bool saw_every_contact(const dealii::Vector<double> &x, int first, int last);
    /// WIREFEM_NEWTON_LOG: a quasi-static step that moved a node by more
    /// than d/4 (a jump between equilibria Newton crossed without failing).
    void log_jump(double step, int first, int last, const dealii::Vector<double> &u1) const;
    /// One implicit step: predictor, then Newton's iteration; commits when
    /// it converges (and the overlap test passes). kept: the linear solves
    /// by GMRES on the kept factors (FEM/Linear solver), otherwise an LU
    /// per iteration.
    StepOutcome solve_step(double step, bool kept = false);
    double free_residual_norm(const Evaluation &ev, int first, int last) const;
    /// The residual norms of the last step's Newton iterations, for the
    /// WIREFEM_NEWTON_LOG lines.
    std::string residual_history() const;
    /// Generalized-alpha's local error of the step x (d, max norm over the
    /// free dofs [first, last)), for FEM/Step error.
    double local_error(const StepState &x, int first, int last) const;
    /// Sets the step's estimates and their larger ratio to the targets; returns it.
    double estimate_errors(const StepState &x, int first, int last, const core::EnergyLedger &after);
    /// The broad phase's candidate pairs for the free range.
    void update_contact_candidates(int first, int last);
    /// The node positions of x, as the broad phase takes them.
    std::vector<Vec2> node_positions(const dealii::Vector<double> &x) const;
    /// Moves x.u1 by the Newton correction dx (with backtracking when
    /// line_search is on); e holds the evaluation at the new x.u1 with its
    /// tangent in K (none when it converged where likely_converges() said
    /// so). Returns its residual norm.
    double newton_update(const AssemblyRequest &rq, StepState &x, const dealii::Vector<double> &dx,
                         double res, Evaluation &e, Evaluation &trial);
    /// Whether the update from residual `res` likely converges (the last
    /// contraction repeated): newton_update then assembles the residual
    /// alone first. Not on the clamp's path (its stability test needs K).
    bool likely_converges(double res) const;
    unsigned long tangents_skipped = 0, tangents_missed = 0; ///< such updates; those not converged
    /// x.u1 = u_start + lambda dx on the free dofs, and its kinematics.
    void move_along(const AssemblyRequest &rq, StepState &x, const dealii::Vector<double> &u_start,
                    const dealii::Vector<double> &dx, double lambda) const;
    /// Backtracking from u_start along dx (Armijo on the max norm, up to
    /// five halvings, residual only); leaves x.u1 at the last point tried.
    void backtrack(const AssemblyRequest &rq, StepState &x, const dealii::Vector<double> &u_start,
                   const dealii::Vector<double> &dx, double res, Evaluation &trial);
    /// newton_update for FEM/Newton = modified. fresh: whether dx was
    /// solved with the tangent at x.u1; on return, whether K holds the
    /// tangent at the new x.u1 (then its factors are to be made), else the
    /// next solve reuses the factors. e holds the evaluation at the new
    /// x.u1. Returns its residual norm.
    double modified_update(const AssemblyRequest &rq, StepState &x, const dealii::Vector<double> &dx,
                           double res, bool &fresh, Evaluation &e, Evaluation &trial);
    /// The predictor of an implicit step of length `step` (free range
    /// [first, last)), with its kinematics.
    void predict(double step, int first, int last, StepState &x) const;
    /// The start of an implicit step of length `step`: the channel mouths
    /// and free range at its end, its predictor x, the contact candidates;
    /// returns the step's assembly request (the generalized-alpha weights
    /// of the mass and forces, the free range) at x.
    AssemblyRequest start_step(double step, StepState &x);
    /// Newton's right-hand side over the free dofs: minus the blended residual.
    void newton_rhs(const Evaluation &ev, const AssemblyRequest &rq, dealii::Vector<double> &rhs) const;
    /// Called (when set) with the first assembly of each implicit step, at
    /// the predictor: the tests compare the tangent K there with finite
    /// differences of the residual (tests/rod_probe.h).
    std::function<void(const AssemblyRequest &, StepState &)> predictor_probe;
    void explicit_step(double step);
    bool explicit_mode = false;
    std::vector<double> lumped_element;                         // row sums of element_mass
    std::vector<double> lumped_mass(int first, int last) const; ///< per dof, the active cells' lumped_element
    double cell_kinetic(unsigned int c, const dealii::Vector<double> &vel) const;
    /// The channels' work over a step into `work` (left, right).
    void channel_work(const dealii::Vector<double> &u1, const Evaluation &e, int work_first, int work_last,
                      bool trapezoid, double (&work)[2]) const;
    /// The ledger after a step to (u1, v1), and the channels' work over it.
    /// The channel work is summed over the prescribed dofs of the free range
    /// [work_first, work_last) (the range the step was solved with).
    struct Booking
    {
      core::EnergyLedger ledger;
      double work[2] = {0, 0};
    };
    Booking book(int first, int last, const dealii::Vector<double> &u1, const dealii::Vector<double> &v1,
                 const Evaluation &e, int work_first, int work_last) const;
    /// FEM/Step energy error: the ledger's imbalance over this step and the
    /// last, over their share (length / time) of the energy in so far.
    double energy_error(const core::EnergyLedger &after, double step, bool with_last = true) const;
    /// Accepts the step, booked as b.
    void commit(double step, int first, int last, const dealii::Vector<double> &u1,
                const dealii::Vector<double> &v1, const dealii::Vector<double> &a1, Evaluation &e,
                const Booking &b);
    double kinetic_energy(const dealii::Vector<double> &vel, int first, int last) const;
    bool cell_active(unsigned int c, int first, int last) const
    {
      for (const auto k : cell_node[c])
        if (static_cast<int>(k) >= first && static_cast<int>(k) < last)
          return true;
      return false;
    }
  };
} // namespace wirefem::fem
