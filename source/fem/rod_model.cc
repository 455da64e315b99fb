#include <wirefem/analysis/observables.h>
#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/segment_distance.h>
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>
#include <wirefem/fem/rod_model.h>
#include <wirefem/fem/sparse_direct.h>
#include <wirefem/injection/channels.h>
#include <wirefem/injection/inlet.h>
#include <wirefem/core/binary.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace wirefem::fem
{
  using core::Vec2;
  using injection::Side;

  namespace
  {
    constexpr std::uint64_t fem_magic = 0x77666d66656d3031ull; // "wfmfem01"

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
      double axial = 0, shear = 0, bending = 0, contact = 0, plastic = 0;
      double max_overlap = 0;
      int n_wall = 0;
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

      /// The part of the velocity that does not depend on u, at node k.
      core::Vec2 velocity0(const int k) const { return {(*v0)[3 * k], (*v0)[3 * k + 1]}; }
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
  } // namespace

  struct RodModel::Impl
  {
    scene::Scene scene;
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
    ContactSettings wall_settings, self_settings;

    unsigned int n_cells = 0, n_nodes = 0, n_local = 0;
    std::vector<double> node_S;                       // material coordinate of node k (sorted)
    std::vector<std::vector<unsigned int>> cell_node; // node of local node a
    double a_left = 0, a_right = 0;                   // material coordinates of the inlets at t = 0
    double min_spacing = 0;

    // Generalized-alpha.
    double alpha_m = 0, alpha_f = 0, beta = 0.25, gamma = 0.5;
    bool inertia = true;

    // State at t_n.
    dealii::Vector<double> u, v, a, f_old;
    std::vector<PointState> qp;
    double t = 0, dt = 0, dt_max = 0;
    unsigned long steps = 0, cuts = 0;
    int first_free = 0, last_free = 0; // free nodes [first, last)
    /// The channels push the wire deeper than `hold` inside them (those nodes
    /// are prescribed); from there to the mouth the channel walls guide it
    /// (fem::channel_wall_element in evaluate()), so a node is let go gradually
    /// as it leaves.
    double hold = 0;
    double k_channel = 0; ///< lateral stiffness of the channel walls per length
    double wall_time = 0; ///< time at which evaluate() places the channel mouths

    contact::BroadPhase broad;
    int exclusion = 1;
    dealii::SparsityPattern sparsity;
    dealii::SparseMatrix<double> K;
    /// K's LU (KLU): analysed once per pattern, refactorised per iteration.
    SparseDirect lu;
    std::vector<int> lu_order; ///< entry of K (storage order) for each entry of the sorted CSR
    std::vector<double> lu_values;
    std::vector<double> lu_stored, lu_rhs, lu_solution; ///< solve_linear's scratch
    /// Factorises K and solves K x = rhs; false when K is singular.
    bool solve_linear(const dealii::Vector<double> &rhs, dealii::Vector<double> &x);
    int sp_first = -1, sp_last = -1;
    std::vector<contact::SegmentPair> sp_pairs;

    core::EnergyLedger ledger;
    core::StepReport last_report;
    injection::ForceWindow window[2];
    std::vector<std::string> effects;
    std::vector<double> history;
    Evaluation latest; ///< at the last accepted state
    dealii::TimerOutput timer;
    std::ostringstream timer_stream;

    explicit Impl(const scene::Scene &s);
    /// The mesh of the whole wire that can ever enter, numbered node by node
    /// along the wire; node coordinates and the element mass matrix.
    void build_mesh(const scene::Scene &s);
    /// Section, material, contact settings, the effects of the run, and the
    /// time integrator's parameters and step.
    void build_physics(const scene::Scene &s);
    /// The seeded shape at rest, its initial acceleration and stored energy.
    void set_initial_state(const scene::Scene &s);

    int node_dof(unsigned int node, unsigned int c) const { return static_cast<int>(3 * node + c); }
    double left_inlet_S(double time) const { return a_left - channels.injected_per_channel(time); }
    double right_inlet_S(double time) const { return a_right + channels.injected_per_channel(time); }
    /// The nodes with material coordinate in (sl, sr).
    void nodes_between(double sl, double sr, int &first, int &last) const;
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

    /// Assembles what the request asks for into e; with want_tangent the
    /// matrix K (dofs of the free range) is filled. One function per
    /// contribution, each adding to e and K.
    void evaluate(const AssemblyRequest &rq, Evaluation &e);
    void assemble_elements(const AssemblyRequest &rq, Evaluation &e);
    void assemble_wall(const AssemblyRequest &rq, Evaluation &e);
    void assemble_channel_walls(const AssemblyRequest &rq, Evaluation &e);
    void assemble_self_contact(const AssemblyRequest &rq, Evaluation &e);
    /// Adds scale * m (the square matrix on the global dofs g, row major)
    /// to K, restricted to the free range.
    void add_matrix(const AssemblyRequest &rq, const std::vector<int> &g, const double *m, double scale);
    /// Adds a contact contribution on the nodes listed (x and y of each).
    void add_contact(const AssemblyRequest &rq, const ContactContribution &cc, const std::vector<int> &nodes,
                     Evaluation &e);
    std::vector<dealii::types::global_dof_index> scratch_rows; ///< add_matrix
    std::vector<int> scratch_pick;                             ///< add_matrix
    dealii::FullMatrix<double> scratch_block;                  ///< add_matrix
    void rebuild_sparsity(int first, int last);
    bool solve_step(double step);
    /// The predictor of an implicit step of length `step` (free range
    /// [first, last)), with its kinematics.
    void predict(double step, int first, int last, StepState &x) const;
    /// max |K - K_fd| / max |K| at x.u1, K assembled there and K_fd the
    /// central differences of the assembled residual (tests).
    double tangent_error_at(const AssemblyRequest &rq, StepState &x);
    bool check_tangent = false;  ///< compare the tangent with finite differences at the next predictor
    double tangent_error = -1.0; ///< max |K - K_fd| / max |K| found there
    void explicit_step(double step);
    bool explicit_mode = false;
    std::vector<double> lumped_element; // row sums of element_mass
    double cell_kinetic(unsigned int c, const dealii::Vector<double> &vel) const
    {
      const unsigned int nd = n_local;
      double ek = 0;
      for (unsigned int i = 0; i < nd; ++i)
        {
          const double vi = vel[3 * cell_node[c][i / 3] + i % 3];
          if (explicit_mode)
            ek += 0.5 * lumped_element[i] * vi * vi;
          else
            for (unsigned int j = 0; j < nd; ++j)
              ek += 0.5 * vi * element_mass[i * nd + j] * vel[3 * cell_node[c][j / 3] + j % 3];
        }
      return ek;
    }
    /// Accepts the step. The channel work is summed over the prescribed dofs
    /// of the free range [work_first, work_last) (the range the step was
    /// solved with).
    void commit(double step, int first, int last, const dealii::Vector<double> &u1,
                const dealii::Vector<double> &v1, const dealii::Vector<double> &a1, Evaluation &e,
                int work_first, int work_last);
    double kinetic_energy(const dealii::Vector<double> &vel, int first, int last) const;
    bool cell_active(unsigned int c, int first, int last) const
    {
      for (const auto k : cell_node[c])
        if (static_cast<int>(k) >= first && static_cast<int>(k) < last)
          return true;
      return false;
    }
  };

  RodModel::Impl::Impl(const scene::Scene &s)
    : scene(s)
    , radius(s.cavity.radius)
    , diameter(1.0)
    , rhoA(s.wire.mass_per_length)
    , rhoI(s.wire.mass_per_length * diameter * diameter / 16.0)
    , channels(s.cavity.radius, s.injection.speed, s.injection.ramp_time, s.injection.slow_start_speed,
               s.injection.slow_start_length)
    , p(s.fem.degree)
    , h(s.fem.element_length)
    , fe(dealii::FE_Q<1, 2>(s.fem.degree), 3)
    , broad(1.0, s.contact.skin, 1)
    , timer(timer_stream, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
  {
    build_mesh(s);
    build_physics(s);
    set_initial_state(s);
  }

  void RodModel::Impl::build_mesh(const scene::Scene &s)
  {
    // The wire the channels can ever push in: phi_max pi r^2 inside, plus
    // two elements of margin in each channel.
    const double L_max = s.injection.maximum_packing_density * M_PI * radius * radius / diameter;
    hold = std::max(2.0 * h, 2.0 * diameter);
    // Tangential channels start from an S of two half circles between the
    // inlets, L0 = pi r' long (not rounded: the mesh need not end at the
    // inlets). As in the discrete model, such a channel holds its wire
    // sqrt(2 r' d) + d further back: wire in the cavity comes within d of
    // its axis up to sqrt(2 r' d) behind the inlet.
    if (s.injection.tangential_channels)
      {
        const double r_inlet = radius - 0.5 * diameter;
        channels.make_tangential(r_inlet, M_PI * r_inlet);
        hold += std::sqrt(2.0 * r_inlet * diameter) + diameter;
      }
    const double L0 = channels.initial_length();
    k_channel = s.contact.normal_stiffness / diameter;
    const double per_channel = 0.5 * (L_max - L0) + 2.0 * h + hold;
    const unsigned int n_channel = static_cast<unsigned int>(std::ceil(per_channel / h));
    const unsigned int n_cavity = static_cast<unsigned int>(std::ceil(L0 / h - 1e-9));
    n_cells = 2 * n_channel + n_cavity;
    a_left = n_channel * h;
    a_right = a_left + L0;

    std::vector<dealii::Point<2>> vertices(n_cells + 1);
    for (unsigned int i = 0; i <= n_cells; ++i)
      vertices[i] = dealii::Point<2>(i * h, 0.0);
    std::vector<dealii::CellData<1>> cells(n_cells);
    for (unsigned int i = 0; i < n_cells; ++i)
      {
        cells[i].vertices[0] = i;
        cells[i].vertices[1] = i + 1;
      }
    tria.create_triangulation(vertices, cells, dealii::SubCellData());
    dof_handler.reinit(tria);
    dof_handler.distribute_dofs(fe);
    n_local = fe.n_dofs_per_cell();
    n_nodes = n_cells * p + 1;

    // Number the dofs node by node along the wire, (x, y, theta) per node,
    // so that the free nodes between the inlets are one contiguous block.
    std::vector<dealii::types::global_dof_index> renumber(dof_handler.n_dofs());
    std::vector<dealii::types::global_dof_index> local(n_local);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int k = static_cast<unsigned int>(std::lround(cell->vertex(0)[0] / h));
        cell->get_dof_indices(local);
        for (unsigned int i = 0; i < n_local; ++i)
          {
            const auto ci = fe.system_to_component_index(i);
            const unsigned int a_ = ci.second;
            const unsigned int node = a_ == 0 ? k * p : a_ == 1 ? (k + 1) * p : k * p + (a_ - 1);
            renumber[local[i]] = 3 * node + ci.first;
          }
      }
    dof_handler.renumber_dofs(renumber);
    cell_node.assign(n_cells, std::vector<unsigned int>(p + 1));
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int k = static_cast<unsigned int>(std::lround(cell->vertex(0)[0] / h));
        cell->get_dof_indices(local);
        for (unsigned int i = 0; i < n_local; ++i)
          {
            const auto ci = fe.system_to_component_index(i);
            if (local[i] % 3 != ci.first)
              throw std::logic_error("RodModel: unexpected dof numbering");
            cell_node[k][ci.second] = static_cast<unsigned int>(local[i] / 3);
          }
      }

    stiffness_shape = ElementShape::lagrange(p, h, p); // reduced: p Gauss points
    mass_shape = ElementShape::lagrange(p, h, p + 1);
    node_S.resize(n_nodes);
    for (unsigned int c = 0; c < n_cells; ++c)
      for (unsigned int a_ = 0; a_ <= p; ++a_)
        node_S[cell_node[c][a_]] = (c + stiffness_shape.node_position[a_]) * h;
    min_spacing = h;
    for (unsigned int k = 0; k + 1 < n_nodes; ++k)
      min_spacing = std::min(min_spacing, node_S[k + 1] - node_S[k]);

    element_mass.assign(9 * (p + 1) * (p + 1), 0.0);
    const unsigned int nd = 3 * (p + 1);
    for (unsigned int q = 0; q < mass_shape.n_q; ++q)
      for (unsigned int i = 0; i <= p; ++i)
        for (unsigned int j = 0; j <= p; ++j)
          for (unsigned int c = 0; c < 3; ++c)
            element_mass[(3 * i + c) * nd + 3 * j + c] += mass_shape.weight[q] * mass_shape.value(q, i) *
                                                          mass_shape.value(q, j) * (c < 2 ? rhoA : rhoI);
  }

  void RodModel::Impl::build_physics(const scene::Scene &s)
  {
    // Section and material.
    const auto &w = s.wire;
    section.EA = w.axial_stiffness;
    section.GA = s.fem.formulation == scene::Formulation::kirchhoff
                     ? s.fem.kirchhoff_penalty * w.axial_stiffness
                     : s.fem.shear_stiffness;
    // The dashpots of the discrete model in the continuum limit.
    section.axial_viscosity = s.discrete.axial_damping * s.discrete.segment_length;
    section.bending_viscosity = s.discrete.rotational_damping * s.discrete.segment_length;
    viscous = section.axial_viscosity > 0 || section.bending_viscosity > 0;
    const auto &pl = w.plasticity;
    const bool keep = s.keep_neutral_effects;
    plastic = s.plastic_bending();
    law = plastic ? material::MomentCurvatureLaw(w.bending_stiffness, pl.yield_curvature, pl.hardening_slope,
                                                 pl.hardening)
                  : material::MomentCurvatureLaw(w.bending_stiffness);

    effects = {"stretching",
               s.fem.formulation == scene::Formulation::kirchhoff ? "shear constraint" : "shear"};
    if (w.bending_stiffness > 0)
      effects.push_back("bending");
    if (plastic)
      effects.push_back("plasticity");
    if (viscous)
      effects.push_back("damping");
    const auto &con = s.contact;
    const auto &fr = con.friction;
    ContactSettings base;
    base.diameter = diameter;
    base.stiffness = con.normal_stiffness;
    base.threshold_velocity = fr.threshold_velocity;
    wall_settings = self_settings = base;
    wall_settings.mu_static = fr.wall_static_coefficient;
    wall_settings.mu_dynamic = fr.wall_dynamic_coefficient;
    wall_settings.friction = con.wall_contact && (keep || fr.wall_static_coefficient > 0);
    wall_settings.mouths = !channels.is_tangential();
    self_settings.mu_static = fr.static_coefficient;
    self_settings.mu_dynamic = fr.dynamic_coefficient;
    self_settings.friction = con.self_contact && (keep || fr.static_coefficient > 0);
    if (con.wall_contact)
      effects.push_back("wall contact");
    if (con.self_contact)
      effects.push_back("self contact");
    if (wall_settings.friction || self_settings.friction)
      effects.push_back("friction");
    const auto integrator = s.fem.integrator;
    inertia = integrator != scene::Integrator::quasi_static;
    if (inertia)
      effects.push_back("inertia");
    exclusion = std::max(1, static_cast<int>(std::ceil(con.exclusion_length / min_spacing - 1e-9)));
    broad = contact::BroadPhase(diameter, con.skin, exclusion);

    if (integrator == scene::Integrator::generalized_alpha)
      {
        const double rho = s.fem.spectral_radius;
        alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
        alpha_f = rho / (rho + 1.0);
        gamma = 0.5 - alpha_m + alpha_f;
        beta = 0.25 * (1.0 - alpha_m + alpha_f) * (1.0 - alpha_m + alpha_f);
      }
    dt_max = s.fem.time_step > 0 ? s.fem.time_step : std::min(0.025, 0.025 * diameter / s.injection.speed);
    if (integrator == scene::Integrator::explicit_lumped)
      {
        // Central differences (symplectic Euler) with the row-sum lumped
        // mass: stable below 2 / omega_max; half of it by default.
        explicit_mode = true;
        const unsigned int nd = n_local;
        lumped_element.assign(nd, 0.0);
        for (unsigned int i = 0; i < nd; ++i)
          for (unsigned int j = 0; j < nd; ++j)
            lumped_element[i] += element_mass[i * nd + j];
        const double hm = min_spacing;
        const double m_t = rhoA * hm, m_r = rhoI * hm;
        const double w2 = std::max(4.0 * (section.EA + section.GA) / (m_t * hm),
                                   (section.GA * hm + 4.0 * w.bending_stiffness / hm) / m_r) +
                          4.0 * con.normal_stiffness * hm / m_t;
        dt_max = s.fem.time_step > 0 ? s.fem.time_step : 0.5 * 2.0 / std::sqrt(w2);
      }
    dt = dt_max;
    for (int side = 0; side < 2; ++side)
      window[side].length = h / p;
  }

  void RodModel::Impl::set_initial_state(const scene::Scene &s)
  {
    const double L0 = channels.initial_length();
    // Initial state: straight in the channels, the seeded shape across the
    // cavity, at rest.
    const unsigned int n_dofs = dof_handler.n_dofs();
    u.reinit(n_dofs);
    v.reinit(n_dofs);
    a.reinit(n_dofs);
    f_old.reinit(n_dofs);
    qp.assign(n_cells * stiffness_shape.n_q, PointState{});
    free_range(0.0, first_free, last_free);
    wall_time = 0.0;
    prescribe(0.0, u, nullptr, nullptr, first_free, last_free);
    if (channels.is_tangential())
      {
        // The S (as the discrete model's: injection::Channels::initial_s).
        // The wire in a channel lies on its axis.
        for (int k = first_free; k < last_free; ++k)
          {
            const double xi = node_S[k] - a_left;
            Vec2 pos;
            double angle = channels.wire_angle();
            if (xi <= 0.0 || xi >= L0)
              pos = xi <= 0.0 ? channels.position(Side::left, xi, 0.0)
                              : channels.position(Side::right, L0 - xi, 0.0);
            else
              {
                const auto p = channels.initial_s(xi);
                pos = p.position;
                angle = p.angle;
              }
            u[3 * k] = pos.x;
            u[3 * k + 1] = pos.y;
            u[3 * k + 2] = angle;
          }
      }
    else
      {
        const injection::InitialShape shape(s.injection.seed, s.injection.perturbation, 2.0 * radius,
                                            s.injection.mirror_asymmetry);
        for (int k = first_free; k < last_free; ++k)
          {
            const double xi = node_S[k] - a_left;
            const bool across = xi > 0.0 && xi < 2.0 * radius; // else in a channel, on its axis
            u[3 * k] = xi - radius;
            u[3 * k + 1] = across ? shape.offset(xi) : 0.0;
            u[3 * k + 2] = across ? std::atan(shape.slope(xi)) : 0.0;
          }
      }
    // The initial acceleration, and the stored energy of the perturbed
    // wire. Where its curvature exceeds the yield curvature the wire starts
    // plastically pre-bent (the return mapping from a virgin state gives the
    // plastic curvature), so that it starts in an admissible state and the
    // initial energy is what is elastically stored.
    Evaluation e;
    dealii::Vector<double> zero(n_dofs);
    if (inertia && !explicit_mode)
      {
        // M a0 = -f(u0) on the free dofs.
        evaluate({&u, &zero, &zero, 0.0, 0.0, first_free, last_free, true, 1.0, 0.0, 0.0}, e);
        dealii::Vector<double> rhs(3 * (last_free - first_free)), x(rhs.size());
        for (unsigned int i = 0; i < rhs.size(); ++i)
          rhs[i] = -e.force[3 * first_free + i];
        if (!solve_linear(rhs, x))
          throw std::runtime_error("the mass matrix of the initial wire is singular");
        for (unsigned int i = 0; i < x.size(); ++i)
          a[3 * first_free + i] = x[i];
        f_old = e.force;
      }
    else
      evaluate({&u, &zero, &zero, 0.0, 0.0, first_free, last_free, false, 0.0, 1.0, 1.0}, e);
    // The strains of the initial shape are the reference of the first rates.
    qp = e.state;
    ledger.initial = e.axial + e.shear + e.bending;
  }

  bool RodModel::Impl::solve_linear(const dealii::Vector<double> &rhs, dealii::Vector<double> &x)
  {
    // K's values in storage order, row by row, as rebuild_sparsity numbered them.
    lu_stored.resize(lu_values.size());
    std::size_t k = 0;
    for (unsigned int i = 0; i < K.m(); ++i)
      for (auto it = K.begin(i); it != K.end(i); ++it)
        lu_stored[k++] = it->value();
    for (std::size_t j = 0; j < lu_order.size(); ++j)
      lu_values[j] = lu_stored[lu_order[j]];
    if (!lu.factorise(lu_values))
      return false;
    lu_rhs.assign(rhs.begin(), rhs.end());
    if (!lu.solve(lu_rhs, lu_solution))
      return false;
    std::copy(lu_solution.begin(), lu_solution.end(), x.begin());
    return true;
  }

  void RodModel::Impl::nodes_between(const double sl, const double sr, int &first, int &last) const
  {
    first = static_cast<int>(std::upper_bound(node_S.begin(), node_S.end(), sl + 1e-12 * h) - node_S.begin());
    last = static_cast<int>(std::lower_bound(node_S.begin(), node_S.end(), sr - 1e-12 * h) - node_S.begin());
  }

  void RodModel::Impl::free_range(const double time, int &first, int &last) const
  {
    nodes_between(left_inlet_S(time) - hold, right_inlet_S(time) + hold, first, last);
    if (first < 1 || last >= static_cast<int>(n_nodes))
      throw std::runtime_error("the wire in the channels is used up (Injection/Maximum packing density "
                               "sets how much wire the mesh holds)");
  }

  void RodModel::Impl::inside_range(const double time, int &first, int &last) const
  {
    nodes_between(left_inlet_S(time), right_inlet_S(time), first, last);
  }

  void RodModel::Impl::prescribe(const double time, dealii::Vector<double> &x, dealii::Vector<double> *vel,
                                 dealii::Vector<double> *acc, const int first, const int last) const
  {
    const double speed = channels.injection_speed(time);
    const double accel = channels.injection_acceleration(time);
    for (unsigned int k = 0; k < n_nodes; ++k)
      {
        const int ki = static_cast<int>(k);
        if (ki >= first && ki < last)
          continue;
        const Side side = ki < first ? Side::left : Side::right;
        const double m = side == Side::left ? node_S[k] - a_left : a_right - node_S[k];
        const Vec2 pos = channels.position(side, m, time);
        const Vec2 axis = channels.axis(side);
        x[3 * k] = pos.x;
        x[3 * k + 1] = pos.y;
        x[3 * k + 2] = channels.wire_angle();
        if (vel)
          {
            (*vel)[3 * k] = speed * axis.x;
            (*vel)[3 * k + 1] = speed * axis.y;
            (*vel)[3 * k + 2] = 0.0;
          }
        if (acc)
          {
            (*acc)[3 * k] = accel * axis.x;
            (*acc)[3 * k + 1] = accel * axis.y;
            (*acc)[3 * k + 2] = 0.0;
          }
      }
  }

  void RodModel::Impl::rebuild_sparsity(const int first, const int last)
  {
    const int lo = 3 * first, n = 3 * (last - first);
    dealii::DynamicSparsityPattern dsp(n, n);
    auto couple = [&](const std::vector<int> &nodes) {
      for (const int ka : nodes)
        for (const int kb : nodes)
          if (ka >= first && ka < last && kb >= first && kb < last)
            for (int ca = 0; ca < 3; ++ca)
              for (int cb = 0; cb < 3; ++cb)
                dsp.add(3 * ka + ca - lo, 3 * kb + cb - lo);
    };
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        couple(std::vector<int>(cell_node[c].begin(), cell_node[c].end()));
    for (const auto &pr : broad.candidates())
      couple({pr.i, pr.i + 1, pr.j, pr.j + 1});
    sparsity.copy_from(dsp);
    K.reinit(sparsity);
    // Sorted rows for KLU (deal.II keeps the diagonal first in each row).
    const int nr = static_cast<int>(sparsity.n_rows());
    std::vector<int> row_start(nr + 1, 0), columns;
    lu_order.clear();
    std::vector<std::pair<int, int>> row;
    int entry = 0;
    for (int i = 0; i < nr; ++i)
      {
        row.clear();
        for (auto it = sparsity.begin(i); it != sparsity.end(i); ++it)
          row.emplace_back(static_cast<int>(it->column()), entry++);
        std::sort(row.begin(), row.end());
        for (const auto &[col, at] : row)
          {
            columns.push_back(col);
            lu_order.push_back(at);
          }
        row_start[i + 1] = static_cast<int>(columns.size());
      }
    lu_values.resize(columns.size());
    lu.analyse(nr, std::move(row_start), std::move(columns));
    sp_first = first;
    sp_last = last;
    sp_pairs = broad.candidates();
  }

  void RodModel::Impl::evaluate(const AssemblyRequest &rq, Evaluation &e)
  {
    const unsigned int n_dofs = rq.u->size();
    e.residual.reinit(n_dofs);
    e.force.reinit(n_dofs);
    e.dissipative.reinit(n_dofs);
    e.friction.reinit(n_dofs);
    e.state.assign(qp.size(), PointState{});
    e.node_contact_force.assign(n_nodes, 0.0);
    e.pairs.clear();
    e.axial = e.shear = e.bending = e.contact = e.plastic = e.max_overlap = 0;
    e.n_wall = 0;
    if (rq.want_tangent)
      {
        if (rq.first != sp_first || rq.last != sp_last || broad.candidates() != sp_pairs)
          rebuild_sparsity(rq.first, rq.last);
        K = 0;
      }
    assemble_elements(rq, e);
    dealii::TimerOutput::Scope ts(timer, "assemble contact");
    assemble_wall(rq, e);
    assemble_channel_walls(rq, e);
    assemble_self_contact(rq, e);
  }

  void RodModel::Impl::add_matrix(const AssemblyRequest &rq, const std::vector<int> &g, const double *m,
                                  const double scale)
  {
    const int lo = 3 * rq.first, hi = 3 * rq.last;
    scratch_rows.clear();
    scratch_pick.clear();
    for (unsigned int i = 0; i < g.size(); ++i)
      if (g[i] >= lo && g[i] < hi)
        {
          scratch_rows.push_back(g[i] - lo);
          scratch_pick.push_back(i);
        }
    if (scratch_rows.empty())
      return;
    scratch_block.reinit(scratch_rows.size(), scratch_rows.size());
    for (unsigned int i = 0; i < scratch_pick.size(); ++i)
      for (unsigned int j = 0; j < scratch_pick.size(); ++j)
        scratch_block(i, j) = scale * m[scratch_pick[i] * g.size() + scratch_pick[j]];
    K.add(scratch_rows, scratch_block);
  }

  void RodModel::Impl::add_contact(const AssemblyRequest &rq, const ContactContribution &cc,
                                   const std::vector<int> &nodes, Evaluation &e)
  {
    std::vector<int> g;
    for (const int k : nodes)
      {
        g.push_back(3 * k);
        g.push_back(3 * k + 1);
      }
    for (unsigned int i = 0; i < g.size(); ++i)
      {
        const double normal = cc.residual[i] - cc.friction_residual[i];
        e.force[g[i]] += normal;
        e.friction[g[i]] += cc.friction_residual[i];
        e.dissipative[g[i]] += cc.friction_residual[i];
        e.residual[g[i]] += rq.blend_force * normal + cc.friction_residual[i];
      }
    if (rq.want_tangent)
      add_matrix(rq, g, cc.tangent.data(), rq.c_force);
    e.contact += cc.energy;
    e.max_overlap = std::max(e.max_overlap, cc.overlap);
  }

  void RodModel::Impl::assemble_elements(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    const int first = rq.first, last = rq.last;
    const auto &a_blend = *rq.a_blend;
    const double step = rq.step, c_mass = rq.c_mass, c_force = rq.c_force, blend_force = rq.blend_force;
    const bool want_tangent = rq.want_tangent;
    dealii::TimerOutput::Scope ts(timer, "assemble elements");
    const unsigned int nd = n_local;
    std::vector<int> g(nd);
    std::vector<double> ue(nd), mat(nd * nd);
    ElementResult er;
    const double viscous_dt = viscous && step > 0 ? step : 0.0;
    for (unsigned int c = 0; c < n_cells; ++c)
      {
        if (!cell_active(c, first, last))
          continue;
        for (unsigned int a_ = 0; a_ <= p; ++a_)
          for (unsigned int cc = 0; cc < 3; ++cc)
            {
              g[3 * a_ + cc] = static_cast<int>(3 * cell_node[c][a_] + cc);
              ue[3 * a_ + cc] = u1[g[3 * a_ + cc]];
            }
        const PointState *old = &qp[c * stiffness_shape.n_q];
        evaluate_rod_element(stiffness_shape, section, law, ue.data(), old, viscous_dt, want_tangent, er,
                             c_force > 0 ? 1.0 / c_force : 1.0);
        for (unsigned int i = 0; i < nd; ++i)
          {
            // Elastic forces are blended over the step, the dissipative
            // (viscous) ones act at the end of it: their work is exactly
            // the dissipation the ledger records.
            const double elastic = er.residual[i] - er.viscous_residual[i];
            e.force[g[i]] += elastic;
            e.dissipative[g[i]] += er.viscous_residual[i];
            double inertial = 0;
            if (inertia)
              for (unsigned int j = 0; j < nd; ++j)
                inertial += element_mass[i * nd + j] * a_blend[g[j]];
            e.residual[g[i]] += blend_force * elastic + er.viscous_residual[i] + inertial;
          }
        if (want_tangent)
          {
            for (unsigned int i = 0; i < nd * nd; ++i)
              mat[i] = c_force * er.tangent[i] + (inertia ? c_mass * element_mass[i] : 0.0);
            add_matrix(rq, g, mat.data(), 1.0);
          }
        std::copy(er.state.begin(), er.state.end(), e.state.begin() + c * stiffness_shape.n_q);
        e.axial += er.axial_energy;
        e.shear += er.shear_energy;
        e.bending += er.bending_energy;
        e.plastic += er.plastic_work;
      }
  }

  void RodModel::Impl::assemble_wall(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    const int first = rq.first, last = rq.last;
    ContactContribution cc;
    // Tangential channels: the wire in them (the end nodes behind each
    // inlet, y > 0 at the left and y < 0 at the right) is the channels',
    // and the wall is a closed circle (wall_settings.mouths).
    if (scene.contact.wall_contact)
      {
        const auto [wall_first, wall_last] =
            channels.is_tangential()
                ? injection::nodes_past_tangential_inlets(first, last, [&](int k) { return u1[3 * k + 1]; })
                : std::pair{first, last};
        for (int k = wall_first; k < wall_last; ++k)
          if (wall_contact(radius, wall_settings, node_weight(k), position(u1, k), rq.velocity0(k), rq.c_vel,
                           cc, rq.friction_scale()))
            {
              add_contact(rq, cc, {k}, e);
              e.node_contact_force[k] += cc.normal_force;
              ++e.n_wall;
            }
      }
  }

  void RodModel::Impl::assemble_channel_walls(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    const int first = rq.first, last = rq.last;
    const double blend_force = rq.blend_force, c_force = rq.c_force;
    const bool want_tangent = rq.want_tangent;
    // The channel walls (as ChannelTerm of the discrete model): a lateral
    // spring k_c per length on the part of the wire inside a channel, energy
    // (k_c/2) times the integral of y^2 over the part of each element with
    // s < 0, s the distance past the mouth along the channel axis and y the
    // offset from it. The mouth is fixed in space, so the energy depends on
    // the positions only and the wire leaving a channel is let go
    // continuously and without loss. The cut xi* (s = 0) of an element
    // crossing the mouth is found by bisection; the gradient carries the
    // moving-end term (k_c/2) y(xi*)^2 h dxi*/dx, and the tangent of such an
    // element is the central difference of that gradient.
    {
      const auto &pos = stiffness_shape.node_position;
      const unsigned int nn = p + 1, nd = 2 * nn;
      std::vector<int> g(nd);
      std::vector<double> X(nd), grad(nd), mat(nd * nd);
      for (const Side side : {Side::left, Side::right})
        {
          const double cut = side == Side::left ? left_inlet_S(wall_time) : right_inlet_S(wall_time);
          const Vec2 inlet = channels.inlet(side), ax = channels.axis(side), n = perp(ax);
          // Only the wire near the mouth in material terms can be in a
          // channel, and only elements with a free node (deeper than hold
          // behind the mouth) take part.
          const int c_lo = std::max(0, static_cast<int>(std::floor((cut - hold) / h)) - 1);
          const int c_hi =
              std::min(static_cast<int>(n_cells) - 1, static_cast<int>(std::floor((cut + hold) / h)) + 1);
          for (int ci = c_lo; ci <= c_hi; ++ci)
            {
              const unsigned int c = static_cast<unsigned int>(ci);
              const double x0 = c * h, x1 = x0 + h;
              if ((side == Side::left ? x0 > cut + hold : x1 < cut - hold) || !cell_active(c, first, last))
                continue;
              for (unsigned int a_ = 0; a_ < nn; ++a_)
                {
                  const Vec2 r = position(u1, cell_node[c][a_]) - inlet;
                  X[2 * a_] = r.x;
                  X[2 * a_ + 1] = r.y;
                  g[2 * a_] = static_cast<int>(3 * cell_node[c][a_]);
                  g[2 * a_ + 1] = g[2 * a_] + 1;
                }
              double energy;
              if (!channel_wall_element(pos, h, k_channel, X.data(), ax, energy, grad.data(),
                                        want_tangent ? mat.data() : nullptr))
                continue;
              for (unsigned int a_ = 0; a_ < nn; ++a_)
                if (dot(Vec2{X[2 * a_], X[2 * a_ + 1]}, ax) < 0.0)
                  e.max_overlap = std::max(e.max_overlap, std::abs(dot(Vec2{X[2 * a_], X[2 * a_ + 1]}, n)));
              for (unsigned int i = 0; i < nd; ++i)
                {
                  e.force[g[i]] += grad[i];
                  e.residual[g[i]] += blend_force * grad[i];
                }
              e.contact += energy;
              if (want_tangent)
                add_matrix(rq, g, mat.data(), c_force);
            }
        }
    }
  }

  void RodModel::Impl::assemble_self_contact(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    const int first = rq.first, last = rq.last;
    ContactContribution cc;
    if (scene.contact.self_contact)
      {
        // Node-to-segment contact, both ways: the first node of each
        // candidate segment against the other segment. Two wires side by
        // side are then pressed apart by a force that moves smoothly along
        // them (segment-to-segment closest points jump between end points
        // of nearly parallel segments, which stalls Newton). Each direction
        // carries half the penalty, so two parallel wires feel k_n per unit
        // length. A node pressed by a stretch of wire feels it once, with a
        // force continuously differentiable in every position
        // (point_stretch_contact: every segment within reach presses it,
        // less the nodes shared by two of them).
        const int first_segment = first - 1, last_segment = last + 1 - 2; // nodes [first - 1, last + 1)
        const double fs = rq.friction_scale();
        const auto at = [&](const int k) { return position(u1, k); };
        const auto allowed = [&](const int node, const int s) {
          return s >= first_segment && s <= last_segment && std::abs(s - node) > exclusion;
        };
        for (const auto &pr : broad.candidates())
          for (const bool a_on_b : {true, false})
            {
              const int node = a_on_b ? pr.i : pr.j, seg = a_on_b ? pr.j : pr.i;
              const std::array<Vec2, 3> x{{at(node), at(seg), at(seg + 1)}};
              const std::array<Vec2, 3> w0{{rq.velocity0(node), rq.velocity0(seg), rq.velocity0(seg + 1)}};
              double tc, fv;
              const bool touch = point_stretch_contact(self_settings, 0.5 * node_weight(node), x, w0,
                                                       rq.c_vel, allowed(node, seg + 1), cc, tc, fv, fs);
              e.max_overlap = std::max(e.max_overlap, cc.overlap);
              if (!touch)
                continue;
              add_contact(rq, cc, {node, seg, seg + 1}, e);
              e.node_contact_force[node] += cc.normal_force - fv;
              e.node_contact_force[seg] += (1.0 - tc) * cc.normal_force;
              e.node_contact_force[seg + 1] += tc * cc.normal_force - fv;
              // The contact network lists the nearest segment of each
              // stretch, as the discrete model's.
              if (!contact::nearest_of_stretch(x[0], seg,
                                               contact::closest_on_segment(x[0], x[1], x[2]).distance2, at,
                                               [&](const int s) { return allowed(node, s); }))
                continue;
              if (a_on_b)
                e.pairs.push_back({node, seg, 0.0, tc, cc.normal_force});
              else
                e.pairs.push_back({seg, node, tc, 0.0, cc.normal_force});
            }
      }
  }

  double RodModel::Impl::kinetic_energy(const dealii::Vector<double> &vel, const int first,
                                        const int last) const
  {
    if (!inertia)
      return 0.0;
    double ek = 0;
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        ek += cell_kinetic(c, vel);
    return ek;
  }

  void RodModel::Impl::explicit_step(const double step)
  {
    const unsigned int n = u.size();
    int first, last;
    free_range(t + step, first, last);
    {
      dealii::TimerOutput::Scope ts(timer, "contact search");
      std::vector<Vec2> x(n_nodes);
      for (unsigned int k = 0; k < n_nodes; ++k)
        x[k] = position(u, k);
      broad.update(x, first_free - 1, last_free + 1);
    }
    // Forces at t_n with the velocities v_n (dashpot rates over the last step).
    Evaluation e;
    const dealii::Vector<double> zero(n);
    wall_time = t;
    evaluate({&u, &zero, &v, step, 0.0, first_free, last_free, false, 0.0, 1.0, 1.0}, e);
    std::vector<double> mass(n, 0.0);
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first_free, last_free))
        for (unsigned int i = 0; i < n_local; ++i)
          mass[3 * cell_node[c][i / 3] + i % 3] += lumped_element[i];
    dealii::Vector<double> u1(u), v1(v), a1(n);
    // The wire outside the inlets at t_n follows the channels to t_{n+1}.
    prescribe(t + step, u1, &v1, &a1, first_free, last_free);
    for (int i = 3 * first_free; i < 3 * last_free; ++i)
      {
        a1[i] = -(e.force[i] + e.dissipative[i]) / mass[i];
        v1[i] = v[i] + step * a1[i];
        u1[i] = u[i] + step * v1[i];
      }
    // Reactions at the prescribed dofs include their share of inertia.
    for (unsigned int i = 0; i < n; ++i)
      if (static_cast<int>(i) < 3 * first_free || static_cast<int>(i) >= 3 * last_free)
        e.residual[i] += mass[i] * a1[i];
    history.assign(1, 0.0);
    commit(step, first, last, u1, v1, a1, e, first_free, last_free);
  }

  void RodModel::Impl::predict(const double step, const int first, const int last, StepState &x) const
  {
    // Constant acceleration for the free dofs, the channel motion for the
    // prescribed ones.
    const unsigned int n = u.size();
    x.u1 = u;
    x.v1.reinit(n);
    x.a1.reinit(n);
    x.v0.reinit(n);
    x.a_blend.reinit(n);
    x.u_hat.reinit(n);
    for (unsigned int i = 0; i < n; ++i)
      x.u1[i] = u[i] + step * v[i] + 0.5 * step * step * a[i];
    prescribe(t + step, x.u1, nullptr, nullptr, first, last);
    x.step = step;
    x.c_vel = inertia ? gamma / (beta * step) : 1.0 / step;
    x.beta = beta;
    x.alpha_m = alpha_m;
    x.inertia = inertia;
    x.a_n = &a;
    for (unsigned int i = 0; i < n; ++i)
      {
        x.u_hat[i] = u[i] + step * v[i] + step * step * (0.5 - beta) * a[i];
        x.v0[i] = inertia ? v[i] + step * (1.0 - gamma) * a[i] - x.c_vel * x.u_hat[i] : -u[i] / step;
      }
    x.update();
  }

  double RodModel::Impl::tangent_error_at(const AssemblyRequest &rq, StepState &x)
  {
    // Central differences of the assembled residual, column by column,
    // against the tangent K assembled at x.u1.
    const int lo = 3 * rq.first, nw = 3 * (rq.last - rq.first);
    Evaluation trial;
    double worst = 0, largest = 0;
    const double eps = 1e-7;
    for (int j = 0; j < nw; ++j)
      {
        const double keep = x.u1[lo + j];
        dealii::Vector<double> rp(nw);
        for (const double sign : {1.0, -1.0})
          {
            x.u1[lo + j] = keep + sign * eps;
            x.update();
            evaluate(rq.without_tangent(), trial);
            for (int i = 0; i < nw; ++i)
              rp[i] += sign * trial.residual[lo + i] / (2 * eps);
          }
        x.u1[lo + j] = keep;
        for (int i = 0; i < nw; ++i)
          {
            const double kij = K.el(i, j);
            worst = std::max(worst, std::abs(kij - rp[i]));
            largest = std::max(largest, std::abs(kij));
          }
      }
    x.update();
    return worst / largest;
  }

  bool RodModel::Impl::solve_step(const double step)
  {
    const double t1 = t + step;
    wall_time = t1;
    int first, last;
    free_range(t1, first, last);
    const unsigned int n = u.size();
    StepState x;
    predict(step, first, last, x);
    auto &u1 = x.u1;
    const double c_mass = inertia ? (1.0 - alpha_m) / (beta * step * step) : 0.0;
    const double c_force = 1.0 - alpha_f;
    const AssemblyRequest rq{&u1,  &x.a_blend, &x.v0,  step,    x.c_vel, first,
                             last, true,       c_mass, c_force, c_force};
    const double scale = scene.wire.axial_stiffness;
    const double tol = scene.fem.newton_tolerance * scale;
    const int lo = 3 * first, nw = 3 * (last - first);
    auto residual_norm = [&](const Evaluation &ev) -> double {
      double r = 0;
      for (int i = 0; i < nw; ++i)
        {
          const double ri = ev.residual[lo + i] + alpha_f * f_old[lo + i];
          if (!std::isfinite(ri))
            return INFINITY;
          r = std::max(r, std::abs(ri));
        }
      return r;
    };

    {
      dealii::TimerOutput::Scope ts(timer, "contact search");
      std::vector<Vec2> xs(n_nodes);
      for (unsigned int k = 0; k < n_nodes; ++k)
        xs[k] = position(u, k);
      broad.update(xs, first - 1, last + 1);
    }

    history.clear();
    Evaluation e, trial;
    dealii::Vector<double> rhs(nw), dx(nw);
    evaluate(rq, e);
    if (check_tangent)
      {
        check_tangent = false;
        tangent_error = tangent_error_at(rq, x);
        evaluate(rq, e);
      }
    double res = residual_norm(e);
    history.push_back(res);
    for (unsigned int it = 0; it < scene.fem.maximum_iterations; ++it)
      {
        if (res <= tol)
          {
            for (unsigned int i = 0; i < n; ++i)
              e.residual[i] += alpha_f * f_old[i];
            commit(step, first, last, u1, x.v1, x.a1, e, first, last);
            return true;
          }
        if (!std::isfinite(res))
          return false;
        for (int i = 0; i < nw; ++i)
          rhs[i] = -(e.residual[lo + i] + alpha_f * f_old[lo + i]);
        {
          dealii::TimerOutput::Scope ts(timer, "linear solve");
          if (!solve_linear(rhs, dx))
            return false;
        }
        // Full Newton update, with the tangent there; if the residual does
        // not drop, backtrack (Armijo on the max norm) and re-linearise.
        const dealii::Vector<double> u_start(u1);
        double lambda = 1.0;
        for (int i = 0; i < nw; ++i)
          u1[lo + i] = u_start[lo + i] + dx[i];
        x.update();
        evaluate(rq, trial);
        double r_new = residual_norm(trial);
        if (r_new < (1.0 - 1e-4) * res)
          {
            std::swap(e, trial);
            res = r_new;
          }
        else
          {
            for (int ls = 0; ls < 5; ++ls)
              {
                lambda *= 0.5;
                for (int i = 0; i < nw; ++i)
                  u1[lo + i] = u_start[lo + i] + lambda * dx[i];
                x.update();
                evaluate(rq.without_tangent(), trial);
                r_new = residual_norm(trial);
                if (r_new < (1.0 - 1e-4 * lambda) * res)
                  break;
              }
            evaluate(rq, e);
            res = residual_norm(e);
          }
        history.push_back(res);
      }
    return false;
  }

  void RodModel::Impl::commit(const double step, const int first, const int last,
                              const dealii::Vector<double> &u1, const dealii::Vector<double> &v1,
                              const dealii::Vector<double> &a1, Evaluation &e, const int work_first,
                              const int work_last)
  {
    const unsigned int n = u.size();
    // Wire that entered the system this step brings its kinetic energy.
    if (first < first_free || last > last_free)
      {
        double before = 0;
        for (unsigned int c = 0; c < n_cells; ++c)
          if (inertia && cell_active(c, first, last) && !cell_active(c, first_free, last_free))
            before += cell_kinetic(c, v);
        ledger.injection_work += before;
      }
    // Channel work: reactions at the prescribed dofs of the active cells.
    std::vector<char> counted(n_nodes, 0);
    double work[2] = {0, 0};
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, work_first, work_last))
        for (const auto k : cell_node[c])
          {
            const int ki = static_cast<int>(k);
            if ((ki >= work_first && ki < work_last) || counted[k])
              continue;
            counted[k] = 1;
            double w = 0;
            for (unsigned int cc = 0; cc < 3; ++cc)
              w += e.residual[3 * k + cc] * (u1[3 * k + cc] - u[3 * k + cc]);
            work[ki < work_first ? 0 : 1] += w;
          }
    const double du = channels.injected_per_channel(t + step) - channels.injected_per_channel(t);
    for (int side = 0; side < 2; ++side)
      {
        ledger.injection_work += work[side];
        window[side].add(du, work[side]);
      }
    // Friction and dashpots: the work of their nodal forces (at the end of
    // the step) against the motion of the nodes. For the dashpots this is
    // N_v (dN/du) du rather than N_v d(eps): the two differ at second order
    // in the step because the strains are nonlinear in u, and only the
    // first is the energy the time step actually removed (the difference
    // made a first-order drift of the balance in dynamic scenes).
    double friction = 0, viscous = 0;
    for (unsigned int i = 0; i < n; ++i)
      {
        const double du_i = u1[i] - u[i];
        friction += e.friction[i] * du_i;
        viscous += (e.dissipative[i] - e.friction[i]) * du_i;
      }
    ledger.friction += friction;
    ledger.plastic += e.plastic;
    ledger.damping += viscous;
    ledger.stretching = e.axial;
    ledger.shear = e.shear;
    ledger.bending = e.bending;
    ledger.contact = e.contact;
    ledger.kinetic = kinetic_energy(v1, first, last);
    last_report = {e.max_overlap, static_cast<int>(e.pairs.size()), e.n_wall};

    u = u1;
    v = v1;
    a = a1;
    f_old = e.force;
    qp = e.state;
    t += step;
    ++steps;
    first_free = first;
    last_free = last;
    latest = std::move(e);
  }

  RodModel::RodModel(const scene::Scene &scene)
    : impl(std::make_unique<Impl>(scene))
  {
  }

  RodModel::~RodModel() = default;

  std::string RodModel::description() const
  {
    const auto &s = impl->scene.fem;
    const std::string integrator = s.integrator == scene::Integrator::quasi_static ? "quasi-static"
                                   : s.integrator == scene::Integrator::explicit_lumped
                                       ? "explicit (lumped mass)"
                                       : fmt::format("generalized-alpha rho = {}", s.spectral_radius);
    return fmt::format("{} rod, degree {}, h = {}, {} dofs, {}, dt {} {:.4g}",
                       s.formulation == scene::Formulation::kirchhoff ? "Kirchhoff" : "Reissner", s.degree,
                       s.element_length, impl->dof_handler.n_dofs(), integrator,
                       impl->explicit_mode ? "=" : "<=", impl->dt_max);
  }

  void RodModel::step()
  {
    auto &m = *impl;
    if (m.explicit_mode)
      {
        m.explicit_step(m.dt);
        return;
      }
    double step = m.dt;
    while (true)
      {
        bool ok = false;
        try
          {
            ok = m.solve_step(step);
          }
        catch (const dealii::ExceptionBase &)
          {
            ok = false;
          }
        if (ok)
          break;
        ++m.cuts;
        if (std::getenv("WIREFEM_NEWTON_LOG"))
          {
            std::string h;
            for (const double r : m.history)
              h += fmt::format(" {:.2e}", r);
            std::cerr << fmt::format("t = {:.5g}: step {:.3g} cut; residuals{}\n", m.t, step, h);
          }
        step *= 0.5;
        if (step < m.scene.fem.minimum_time_step)
          throw std::runtime_error(fmt::format("Newton did not converge at t = {:.6g} even with the time "
                                               "step cut to {:.3g} (below FEM/Minimum "
                                               "time step {:.3g}); last residual {:.3g}",
                                               m.t, 2.0 * step, m.scene.fem.minimum_time_step,
                                               m.history.empty() ? NAN : m.history.back()));
      }
    if (const char *log = std::getenv("WIREFEM_NEWTON_LOG"); log && std::string(log) == "all")
      {
        std::string h;
        for (const double r : m.history)
          h += fmt::format(" {:.2e}", r);
        std::cerr << fmt::format("t = {:.5g}: step {:.3g} converged; residuals{}\n", m.t, step, h);
      }
    // Grow the step again when Newton had an easy time.
    m.dt = m.history.size() <= 4 ? std::min(m.dt_max, 1.5 * step) : step;
  }

  double RodModel::time() const
  {
    return impl->t;
  }
  double RodModel::time_step() const
  {
    return impl->dt;
  }
  unsigned long RodModel::n_steps() const
  {
    return impl->steps;
  }
  double RodModel::injected_length() const
  {
    return impl->channels.injected_length(impl->t);
  }
  double RodModel::force_left() const
  {
    return impl->window[0].mean();
  }
  double RodModel::force_right() const
  {
    return impl->window[1].mean();
  }
  const core::EnergyLedger &RodModel::energies() const
  {
    return impl->ledger;
  }
  core::StepReport RodModel::report() const
  {
    return impl->last_report;
  }
  const std::vector<std::string> &RodModel::active_effects() const
  {
    return impl->effects;
  }
  const std::vector<double> &RodModel::newton_history() const
  {
    return impl->history;
  }
  unsigned long RodModel::n_step_cuts() const
  {
    return impl->cuts;
  }

  double RodModel::step_checking_tangent()
  {
    impl->check_tangent = true;
    impl->tangent_error = -1.0;
    step();
    return impl->tangent_error;
  }
  unsigned int RodModel::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }

  bool RodModel::finite() const
  {
    for (int i = 3 * impl->first_free; i < 3 * impl->last_free; ++i)
      if (!std::isfinite(impl->u[i]) || !std::isfinite(impl->v[i]))
        return false;
    return true;
  }

  core::WireState RodModel::wire_state() const
  {
    const auto &m = *impl;
    core::WireState w;
    w.diameter = m.diameter;
    w.cavity_radius = m.radius;
    w.time = m.t;
    w.injected_length = injected_length();
    // The inlets, and the free nodes between them.
    const double s0 = m.left_inlet_S(m.t);
    int k0, k1;
    m.inside_range(m.t, k0, k1);
    const int n = k1 - k0 + 2;
    w.points.resize(n);
    w.arc_length.resize(n);
    w.curvature.assign(n, 0.0);
    w.plastic_curvature.assign(n, 0.0);
    w.bending_energy.assign(n, 0.0);
    w.contact_force.assign(n, 0.0);
    w.points[0] = m.channels.inlet(Side::left);
    w.points[n - 1] = m.channels.inlet(Side::right);
    w.arc_length[n - 1] = injected_length();
    const double EI = m.scene.wire.bending_stiffness;
    // Curvature and plastic curvature at a node: mean over the quadrature
    // points of the elements around it.
    std::vector<double> kappa(m.n_nodes, 0.0), kappa_p(m.n_nodes, 0.0), count(m.n_nodes, 0.0);
    const unsigned int nq = m.stiffness_shape.n_q;
    for (unsigned int c = 0; c < m.n_cells; ++c)
      if (m.cell_active(c, k0, k1))
        for (const auto k : m.cell_node[c])
          for (unsigned int q = 0; q < nq; ++q)
            {
              kappa[k] += m.qp[c * nq + q].curvature;
              kappa_p[k] += m.qp[c * nq + q].plastic.plastic_strain;
              count[k] += 1.0;
            }
    for (int k = k0; k < k1; ++k)
      {
        const int i = k - k0 + 1;
        w.points[i] = m.position(m.u, k);
        w.arc_length[i] = m.node_S[k] - s0;
        if (count[k] > 0)
          {
            w.curvature[i] = kappa[k] / count[k];
            w.plastic_curvature[i] = kappa_p[k] / count[k];
          }
        const double ke = w.curvature[i] - w.plastic_curvature[i];
        w.bending_energy[i] = 0.5 * EI * ke * ke * m.node_weight(k);
        if (!m.latest.node_contact_force.empty())
          w.contact_force[i] = m.latest.node_contact_force[k];
      }
    auto point_of = [&](int k, double s) {
      return std::clamp(static_cast<int>(std::lround(k - k0 + 1 + s)), 0, n - 1);
    };
    for (const auto &pr : m.latest.pairs)
      {
        core::SelfContact sc;
        sc.s_a = m.node_S[pr.i] + pr.s * (m.node_S[pr.i + 1] - m.node_S[pr.i]) - s0;
        sc.s_b = m.node_S[pr.j] + pr.t * (m.node_S[pr.j + 1] - m.node_S[pr.j]) - s0;
        sc.point_a = point_of(pr.i, pr.s);
        sc.point_b = point_of(pr.j, pr.t);
        sc.x_a = (1.0 - pr.s) * m.position(m.u, pr.i) + pr.s * m.position(m.u, pr.i + 1);
        sc.x_b = (1.0 - pr.t) * m.position(m.u, pr.j) + pr.t * m.position(m.u, pr.j + 1);
        sc.normal_force = pr.fn;
        w.self_contacts.push_back(sc);
      }
    return w;
  }

  namespace
  {
    void write_dealii_vector(std::ostream &out, const dealii::Vector<double> &x)
    {
      const std::vector<double> v(x.begin(), x.end());
      core::write_vector(out, v, 0, v.size());
    }
    void read_dealii_vector(std::istream &in, dealii::Vector<double> &x)
    {
      std::vector<double> v(x.size());
      if (core::peek_vector_size(in) != v.size())
        throw std::runtime_error("checkpoint does not fit this scene");
      core::read_vector(in, v);
      std::copy(v.begin(), v.end(), x.begin());
    }
  } // namespace

  void RodModel::save(std::ostream &out) const
  {
    const auto &m = *impl;
    core::write_raw(out, fem_magic);
    core::write_raw(out, static_cast<std::uint64_t>(m.u.size()));
    for (const auto *x : {&m.u, &m.v, &m.a, &m.f_old})
      write_dealii_vector(out, *x);
    core::write_vector(out, m.qp, 0, m.qp.size());
    core::write_raw(out, m.t);
    core::write_raw(out, m.dt);
    core::write_raw(out, m.steps);
    core::write_raw(out, m.cuts);
    core::write_raw(out, m.first_free);
    core::write_raw(out, m.last_free);
    core::write_raw(out, m.ledger);
    for (const auto &w : m.window)
      {
        core::write_raw(out, w.injected);
        core::write_raw(out, w.work);
        const std::vector<std::pair<double, double>> steps(w.steps.begin(), w.steps.end());
        core::write_vector(out, steps, 0, steps.size());
      }
  }

  void RodModel::load(std::istream &in)
  {
    auto &m = *impl;
    if (core::read_raw<std::uint64_t>(in) != fem_magic)
      throw std::runtime_error("not a checkpoint of the FEM model");
    if (core::read_raw<std::uint64_t>(in) != m.u.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    for (auto *x : {&m.u, &m.v, &m.a, &m.f_old})
      read_dealii_vector(in, *x);
    if (core::peek_vector_size(in) != m.qp.size())
      throw std::runtime_error("checkpoint does not fit this scene");
    core::read_vector(in, m.qp);
    m.t = core::read_raw<double>(in);
    m.dt = core::read_raw<double>(in);
    m.steps = core::read_raw<unsigned long>(in);
    m.cuts = core::read_raw<unsigned long>(in);
    m.first_free = core::read_raw<int>(in);
    m.last_free = core::read_raw<int>(in);
    m.ledger = core::read_raw<core::EnergyLedger>(in);
    for (auto &w : m.window)
      {
        w.injected = core::read_raw<double>(in);
        w.work = core::read_raw<double>(in);
        std::vector<std::pair<double, double>> steps(core::peek_vector_size(in));
        core::read_vector(in, steps);
        w.steps.assign(steps.begin(), steps.end());
      }
    m.broad.invalidate();
  }

  void RodModel::print_timing(std::ostream &out) const
  {
    impl->timer.print_summary();
    out << impl->timer_stream.str();
    impl->timer_stream.str("");
    out << fmt::format("Newton step cuts: {}\n", impl->cuts);
    const auto &ls = impl->lu.statistics();
    out << fmt::format(
        "linear solves: {} (patterns analysed {}, full factorisations {}, refactorisations {}, "
        "refactorisations redone for accuracy {})\n",
        ls.solves, ls.analyses, ls.factorisations, ls.refactorisations, ls.inaccurate);
  }
} // namespace wirefem::fem
