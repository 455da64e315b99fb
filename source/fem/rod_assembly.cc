#include "rod_model_impl.h"

namespace wirefem::fem
{
  bool RodModel::Impl::solve_linear(const dealii::Vector<double> &rhs, dealii::Vector<double> &x,
                                    const double tolerance)
  {
    if (tolerance <= 0.0)
      return factorise_K() && solve_factorised(rhs, x);
    lu_rhs.assign(rhs.begin(), rhs.end());
    const int iterations = static_cast<int>(scene.fem.krylov_iterations);
    if (!(band_solver ? lu.solve_band(K.values(), lu_rhs, lu_solution, tolerance, iterations,
                                      static_cast<int>(scene.fem.degree))
                      : lu.solve_kept(K.values(), lu_rhs, lu_solution, tolerance, iterations)))
      return false;
    std::copy(lu_solution.begin(), lu_solution.end(), x.begin());
    return true;
  }

  bool RodModel::Impl::factorise_K()
  {
    return lu.factorise(K.values());
  }

  bool RodModel::Impl::solve_factorised(const dealii::Vector<double> &rhs, dealii::Vector<double> &x)
  {
    lu_rhs.assign(rhs.begin(), rhs.end());
    if (!lu.solve(lu_rhs, lu_solution))
      return false;
    std::copy(lu_solution.begin(), lu_solution.end(), x.begin());
    return true;
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
    e.axial = e.shear = e.bending = e.contact = e.plastic = e.max_overlap = e.friction_damping = 0;
    e.push_force = e.friction_stored = 0;
    e.wall_history.clear();
    e.self_history.clear();
    e.n_wall = 0;
    if (rq.want_tangent)
      {
        core::SectionTimer::Scope ts(timer, "sparsity pattern");
        // K's pattern holds the elements of the free range and the
        // candidate pairs within pattern_margin of contact when it was
        // built; it is built anew when the free range changes or a pair
        // that can touch (closer than the contact distance) is not in it.
        const double reach = contact_reach(*rq.u, rq.first, rq.last);
        if (rq.first != sp_first || rq.last != sp_last || !pattern_covers(*rq.u, reach))
          {
            std::vector<contact::SegmentPair> near;
            near_pairs(*rq.u, reach - diameter + pattern_margin, near);
            rebuild_sparsity(rq.first, rq.last, std::move(near));
          }
        K.zero();
      }
    assemble_elements(rq, e);
    if (drag > 0 && inertia)
      assemble_drag(rq, e);
    if (clamped)
      {
        assemble_end_load(e);
        return;
      }
    if (capstan)
      assemble_capstan_loads(rq, e);
    core::SectionTimer::Scope ts(timer, "assemble contact");
    assemble_wall(rq, e);
    if (capstan)
      {
        constrain_trailing_end(rq, e);
        return;
      }
    assemble_channel_walls(rq, e);
    assemble_self_contact(rq, e);
  }

  void RodModel::Impl::assemble_end_load(Evaluation &e) const
  {
    // A dead force on the last node and a moment on its section angle
    // (conservative in the plane).
    const auto &cl = scene.cantilever;
    const unsigned int tip = n_nodes - 1;
    const double load[3] = {cl.end_force_x, cl.end_force_y, cl.end_moment};
    for (unsigned int c = 0; c < 3; ++c)
      {
        e.residual[3 * tip + c] -= load_factor * load[c];
        e.force[3 * tip + c] -= load_factor * load[c];
      }
  }

  void RodModel::Impl::add_matrix(const AssemblyRequest &rq, const int *g, const int n, const double *m,
                                  const double scale)
  {
    const int lo = 3 * rq.first, hi = 3 * rq.last;
    constexpr int most = 18; // an element of degree 5, or a contact of 9 nodes
    assert(n <= most);
    int local[most], component[most];
    for (int i = 0; i < n; ++i)
      {
        local[i] = g[i] >= lo && g[i] < hi ? g[i] - lo : -1;
        component[i] = g[i] % 3;
      }
    K.add_block(local, component, n, m, scale);
  }

  void RodModel::Impl::add_contact(const AssemblyRequest &rq, const ContactContribution &cc,
                                   const std::initializer_list<int> nodes, Evaluation &e)
  {
    int g[6];
    int n = 0;
    for (const int k : nodes)
      {
        g[n++] = 3 * k;
        g[n++] = 3 * k + 1;
      }
    add_contact_forces(rq, g, n, cc.residual.data(), cc.friction_residual.data(), e);
    if (rq.want_tangent)
      add_matrix(rq, g, n, cc.tangent.data(), rq.c_force);
    e.contact += cc.energy;
    e.max_overlap = std::max(e.max_overlap, cc.overlap);
  }

  void RodModel::Impl::add_contact_forces(const AssemblyRequest &rq, const int *g, const int n,
                                          const double *residual, const double *friction, Evaluation &e)
  {
    for (int i = 0; i < n; ++i)
      {
        const double normal = residual[i] - friction[i];
        e.force[g[i]] += normal;
        e.friction[g[i]] += friction[i];
        e.dissipative[g[i]] += friction[i];
        e.residual[g[i]] += rq.blend_force * normal + friction[i];
      }
  }

  void RodModel::Impl::assemble_elements(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    const int first = rq.first, last = rq.last;
    const auto &a_blend = *rq.a_blend;
    const double step = rq.step, c_mass = rq.c_mass, c_force = rq.c_force, blend_force = rq.blend_force;
    const bool want_tangent = rq.want_tangent;
    core::SectionTimer::Scope ts(timer, "assemble elements");
    const unsigned int nd = n_local;
    std::vector<int> g(nd);
    std::vector<double> ue(nd), mat(nd * nd);
    ElementResult er;
    // A quasi-static step's rates are over the time its injection takes:
    // its dashpots only with FEM/Quasi-static dashpots.
    const bool dashpots = viscous && (scene.fem.quasi_static_dashpots || !quasi_static_step());
    const double viscous_dt = dashpots && step > 0 ? step : 0.0;
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
            K.add_at(&cell_position[static_cast<std::size_t>(c) * nd * nd], static_cast<int>(nd * nd),
                     mat.data(), 1.0);
          }
        std::copy(er.state.begin(), er.state.end(), e.state.begin() + c * stiffness_shape.n_q);
        e.axial += er.axial_energy;
        e.shear += er.shear_energy;
        e.bending += er.bending_energy;
        e.plastic += er.plastic_work;
      }
  }

  void RodModel::Impl::assemble_drag(const AssemblyRequest &rq, Evaluation &e)
  {
    // -gamma m v on the positions of the free nodes, m the lumped mass of
    // the elements around a node (the discrete model's drag, m per node):
    // a dissipative force at the end of the step, as the dashpots'.
    const int lo = 3 * rq.first;
    const std::vector<double> mass = lumped_mass(rq.first, rq.last);
    for (int k = rq.first; k < rq.last; ++k)
      for (int c = 0; c < 2; ++c)
        {
          const int i = 3 * k + c;
          const double m = drag * mass[i];
          const double f = m * (rq.c_vel * (*rq.u)[i] + (*rq.v0)[i]);
          e.residual[i] += f;
          e.dissipative[i] += f;
          if (rq.want_tangent)
            {
              const int at = K.find(i - lo, i - lo);
              const double d = m * rq.c_vel;
              K.add_at(&at, 1, &d, 1.0);
            }
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
        if (!segment_points.empty())
          {
            // The segments between the wall's nodes: none reaches into a channel.
            assemble_wall_along(rq, wall_first, wall_last - 1, e);
            return;
          }
        const bool spring = wall_spring && rq.step > 0.0;
        if (spring)
          e.wall_history.assign(n_nodes, contact::FrictionHistory{});
        cc.want_tangent = rq.want_tangent; // (the spring law honours it)
        for (int k = wall_first; k < wall_last; ++k)
          if (spring ? wall_spring_contact(rq, k, position(u1, k), node_weight(k), cc, e)
                     : wall_contact(radius, wall_settings, node_weight(k), position(u1, k), rq.velocity0(k),
                                    rq.friction_c_vel(), cc, rq.friction_scale()))
            {
              add_contact(rq, cc, {k}, e);
              e.node_contact_force[k] += cc.normal_force;
              if (!spring)
                e.friction_damping =
                    std::max(e.friction_damping, friction_damping(wall_settings, cc.normal_force));
              ++e.n_wall;
            }
      }
  }

  bool RodModel::Impl::wall_spring_contact(const AssemblyRequest &rq, const unsigned int i, const Vec2 &x,
                                           const double weight, ContactContribution &cc, Evaluation &e) const
  {
    // The spring law: a sticking spring per wall site, whose history is
    // the last accepted step's; the trial is kept in e.
    SpringFriction sf;
    const bool touching = wall_contact_spring(
        radius, wall_settings, weight, scene.contact.friction.tangential_stiffness_ratio, x, spring_from[i],
        rq.friction_step(), wall_springs[i], cc, sf, rq.friction_scale());
    if (touching)
      {
        e.wall_history[i] = sf.history;
        e.friction_stored += sf.stored;
      }
    return touching;
  }

  void RodModel::Impl::self_spring_friction(const AssemblyRequest &rq, const int node, const int seg,
                                            Evaluation &e)
  {
    // The spring of the last accepted step (or the one the node had on a
    // neighbouring segment), elongated by the slip since that step; the
    // trial is kept in e.
    const std::array<Vec2, 3> x{{position(*rq.u, node), position(*rq.u, seg), position(*rq.u, seg + 1)}};
    const std::array<Vec2, 3> x_old{{position(u, node), position(u, seg), position(u, seg + 1)}};
    ContactContribution fc;
    fc.want_tangent = rq.want_tangent;
    SpringFriction sf;
    if (!point_segment_spring_friction(
            self_settings, 0.5 * node_weight(node), scene.contact.friction.tangential_stiffness_ratio, x,
            x_old, rq.friction_step(), self_springs.find(node, seg), fc, sf, rq.friction_scale()))
      return;
    add_contact(rq, fc, {node, seg, seg + 1}, e);
    e.self_history.push_back({node, seg, sf.history.elongation, sf.history.sliding ? 1 : 0});
    e.friction_stored += sf.stored;
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
          if (!channels.pushes(side))
            continue;
          const double cut = side == Side::left ? left_inlet_S(wall_time) : right_inlet_S(wall_time);
          const Vec2 inlet = channels.cut_origin(side), ax = channels.cut_normal(side),
                     n = perp(channels.axis(side));
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
              if (!channel_wall_element(pos, h, k_channel, X.data(), ax, n, energy, grad.data(),
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
                add_matrix(rq, g.data(), static_cast<int>(nd), mat.data(), c_force);
            }
        }
    }
  }

  void RodModel::Impl::assemble_self_contact(const AssemblyRequest &rq, Evaluation &e)
  {
    const auto &u1 = *rq.u;
    ContactContribution cc;
    if (scene.contact.self_contact && !segment_points.empty())
      assemble_self_contact_along(rq, e);
    else if (scene.contact.self_contact)
      {
        // Node-to-segment contact, both ways: the first node of each
        // candidate segment against the other segment. Two wires side by
        // side are then pressed apart by a force that moves smoothly along
        // them (segment-to-segment closest points jump between end points of
        // nearly parallel segments, which stalls Newton). Each direction carries
        // half the penalty, so two parallel wires feel k_n per unit length. A
        // node pressed by a stretch of wire feels it once, with a force
        // continuously differentiable in every position (point_stretch_contact:
        // every segment within reach presses it, less the nodes shared by two).
        const int first_segment = rq.first - 1,
                  last_segment = past(rq.last) - 2; // nodes [first - 1, past(last))
        const double fs = rq.friction_scale();
        const auto at = [&](const int k) { return position(u1, k); };
        const auto allowed = [&](const int node, const int s) {
          return s >= first_segment && s <= last_segment && std::abs(s - node) > exclusion;
        };
        // With one channel the wire's free tip begins no segment: it presses the
        // other segment of each pair that holds the last segment, as a third way.
        const int tip = channels.pushes(Side::right) ? -1 : static_cast<int>(n_nodes) - 1;
        // The spring law (FEM/Self friction law): the pairs press without
        // friction; each node's friction acts once per stretch, on the
        // stretch's nearest segment, as in the discrete model.
        const bool spring = self_spring && rq.step > 0.0;
        ContactSettings pressing = self_settings;
        pressing.friction = pressing.friction && !spring;
        cc.want_tangent = rq.want_tangent;
        for (const auto &pr : broad.candidates())
          {
            // Boxes a diameter apart: no node of either segment touches the other.
            if (contact::box_gap(at(pr.i), at(pr.i + 1), at(pr.j), at(pr.j + 1)) >= self_settings.diameter)
              continue;
            for (const int way : {0, 1, 2, 3})
              {
                const bool a_on_b = way == 0 || way == 2;
                if (way >= 2 && (a_on_b ? pr.i : pr.j) + 1 != tip)
                  continue;
                const int node = (a_on_b ? pr.i : pr.j) + (way >= 2 ? 1 : 0), seg = a_on_b ? pr.j : pr.i;
                const std::array<Vec2, 3> x{{at(node), at(seg), at(seg + 1)}};
                const std::array<Vec2, 3> w0{{rq.velocity0(node), rq.velocity0(seg), rq.velocity0(seg + 1)}};
                double tc, fv;
                const bool touch =
                    point_stretch_contact(pressing, 0.5 * node_weight(node), x, w0, rq.friction_c_vel(),
                                          allowed(node, seg + 1), cc, tc, fv, fs);
                e.max_overlap = std::max(e.max_overlap, cc.overlap);
                if (!touch)
                  continue;
                add_contact(rq, cc, {node, seg, seg + 1}, e);
                if (!spring)
                  e.friction_damping =
                      std::max(e.friction_damping, friction_damping(self_settings, cc.normal_force));
                e.node_contact_force[node] += cc.normal_force - fv;
                e.node_contact_force[seg] += (1.0 - tc) * cc.normal_force;
                e.node_contact_force[seg + 1] += tc * cc.normal_force - fv;
                // The contact network lists the nearest segment of each
                // stretch, as the discrete model's.
                if (!contact::nearest_of_stretch(x[0], seg,
                                                 contact::closest_on_segment(x[0], x[1], x[2]).distance2, at,
                                                 [&](const int s) { return allowed(node, s); }))
                  continue;
                if (spring)
                  self_spring_friction(rq, node, seg, e);
                // (The tip is the end, s = 1, of the last segment.)
                const int own = way >= 2 ? node - 1 : node;
                const double at_own = way >= 2 ? 1.0 : 0.0;
                if (a_on_b)
                  e.pairs.push_back({own, seg, at_own, tc, cc.normal_force});
                else
                  e.pairs.push_back({seg, own, tc, at_own, cc.normal_force});
              }
          }
      }
  }
} // namespace wirefem::fem
