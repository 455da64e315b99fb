// Contact along the element (FEM/Contact points > 0): the wall and the
// self contact at Gauss points of each segment, on its element's curve,
// carried to the element's nodes by the shape functions.
#include "rod_model_impl.h"

#include <deal.II/base/quadrature_lib.h>

namespace wirefem::fem
{
  void RodModel::Impl::set_up_contact_points(const unsigned int n_points)
  {
    segment_points.clear();
    if (n_points == 0)
      return;
    // Segment k joins nodes k and k + 1 of cell k / p.
    const auto &pos = stiffness_shape.node_position;
    const auto local_of = [&](const unsigned int c, const unsigned int node) {
      return std::find(cell_node[c].begin(), cell_node[c].end(), node) - cell_node[c].begin();
    };
    const dealii::QGauss<1> gauss(n_points);
    std::array<double, 4> dN{};
    segment_points.resize(n_nodes - 1);
    for (unsigned int k = 0; k + 1 < n_nodes; ++k)
      {
        const unsigned int c = k / p;
        const double xi0 = pos[local_of(c, k)], xi1 = pos[local_of(c, k + 1)];
        for (unsigned int q = 0; q < n_points; ++q)
          {
            ContactPoint cp{c, gauss.point(q)[0], gauss.weight(q) * (node_S[k + 1] - node_S[k]), {}};
            lagrange_basis(pos, xi0 + cp.along * (xi1 - xi0), cp.N.data(), dN.data());
            segment_points[k].push_back(cp);
          }
      }
  }

  double RodModel::Impl::contact_reach(const dealii::Vector<double> &x, const int first, const int last) const
  {
    // Contact points on an element's curve lie off the chord between its
    // nodes: two segments can touch with their chords that much farther
    // than d apart.
    double bulge = 0.0;
    if (!segment_points.empty() && p > 1)
      for (int k = std::max(first - 1, 0); k + 1 < std::min(last + 1, static_cast<int>(n_nodes)); ++k)
        for (const auto &cp : segment_points[k])
          {
            const Vec2 xp = point_position(x, cp);
            bulge = std::max(
                bulge,
                std::sqrt(contact::closest_on_segment(xp, position(x, k), position(x, k + 1)).distance2));
          }
    return diameter + 2.0 * bulge;
  }

  void RodModel::Impl::add_point_on_cell(const AssemblyRequest &rq, const ContactContribution &cc,
                                         const unsigned int cell, const std::array<double, 4> &N,
                                         const int seg, Evaluation &e)
  {
    // The contact's point x = sum_a N_a X_a: its rows and columns of the
    // contribution (points: x, the segment's two nodes) carried to the
    // cell's nodes by N, x = P (X_cell, x_seg, x_seg+1), so the residual
    // becomes P^T r and the tangent P^T T P.
    const auto &nodes = cell_node[cell];
    const int n_cell = static_cast<int>(nodes.size()), rows = seg >= 0 ? 6 : 2, n = 2 * n_cell + rows - 2;
    constexpr int most = 2 * 4 + 4;
    int g[most];
    for (int l = 0; l < n_cell; ++l)
      {
        g[2 * l] = 3 * static_cast<int>(nodes[l]);
        g[2 * l + 1] = 3 * static_cast<int>(nodes[l]) + 1;
      }
    for (int m = 0; m < rows - 2; ++m)
      g[2 * n_cell + m] = 3 * (seg + m / 2) + m % 2;
    // Row r of the contribution goes to the columns (and weights) of P.
    const auto spread = [&](const int r, const auto &to) {
      if (r < 2)
        for (int l = 0; l < n_cell; ++l)
          to(2 * l + r, N[l]);
      else
        to(2 * n_cell + r - 2, 1.0);
    };
    double residual[most] = {}, friction[most] = {};
    for (int r = 0; r < rows; ++r)
      spread(r, [&](const int c, const double w) {
        residual[c] += w * cc.residual[r];
        friction[c] += w * cc.friction_residual[r];
      });
    add_contact_forces(rq, g, n, residual, friction, e);
    if (rq.want_tangent)
      {
        double mat[most * most] = {};
        for (int r = 0; r < rows; ++r)
          for (int c = 0; c < rows; ++c)
            spread(r, [&](const int i, const double wi) {
              spread(c, [&](const int j, const double wj) {
                mat[i * n + j] += wi * wj * cc.tangent[r * rows + c];
              });
            });
        add_matrix(rq, g, n, mat, rq.c_force);
      }
    e.contact += cc.energy;
    e.max_overlap = std::max(e.max_overlap, cc.overlap);
  }

  Vec2 RodModel::Impl::point_position(const dealii::Vector<double> &x, const ContactPoint &cp) const
  {
    Vec2 xp{0.0, 0.0};
    const auto &nodes = cell_node[cp.cell];
    for (std::size_t l = 0; l < nodes.size(); ++l)
      xp += cp.N[l] * position(x, nodes[l]);
    return xp;
  }

  Vec2 RodModel::Impl::point_velocity0(const AssemblyRequest &rq, const ContactPoint &cp) const
  {
    Vec2 vp{0.0, 0.0};
    const auto &nodes = cell_node[cp.cell];
    for (std::size_t l = 0; l < nodes.size(); ++l)
      vp += cp.N[l] * rq.velocity0(nodes[l]);
    return vp;
  }

  unsigned int RodModel::Impl::n_wall_sites() const
  {
    return segment_points.empty() ? n_nodes : (n_nodes - 1) * scene.fem.contact_points;
  }

  void RodModel::Impl::assemble_wall_along(const AssemblyRequest &rq, const int first, const int last,
                                           Evaluation &e)
  {
    const bool spring = wall_spring && rq.step > 0.0;
    if (spring)
      e.wall_history.assign(n_wall_sites(), contact::FrictionHistory{});
    const unsigned int n_points = scene.fem.contact_points;
    ContactContribution cc;
    for (int k = std::max(first, 0); k < std::min(last, static_cast<int>(n_nodes) - 1); ++k)
      for (unsigned int q = 0; q < n_points; ++q)
        {
          const auto &cp = segment_points[k][q];
          const auto &nodes = cell_node[cp.cell];
          const Vec2 xp = point_position(*rq.u, cp);
          // The spring law needs no velocity.
          if (!(spring ? wall_spring_contact(rq, k * n_points + q, xp, cp.weight, cc, e)
                       : wall_contact(radius, wall_settings, cp.weight, xp, point_velocity0(rq, cp),
                                      rq.friction_c_vel(), cc, rq.friction_scale())))
            continue;
          add_point_on_cell(rq, cc, cp.cell, cp.N, -1, e);
          for (std::size_t l = 0; l < nodes.size(); ++l)
            e.node_contact_force[nodes[l]] += cp.N[l] * cc.normal_force;
          if (!spring)
            e.friction_damping =
                std::max(e.friction_damping, friction_damping(wall_settings, cc.normal_force));
          ++e.n_wall;
        }
  }

  void RodModel::Impl::assemble_self_contact_along(const AssemblyRequest &rq, Evaluation &e)
  {
    // As the node-to-segment contact (assemble_self_contact), with the
    // contact points of each candidate segment, on its element's curve, in
    // place of its first node: both ways, half the penalty each, each point
    // pressed once by the stretch of wire it faces (point_stretch_contact).
    const auto &u1 = *rq.u;
    const int first_segment = rq.first - 1, last_segment = past(rq.last) - 2;
    const double fs = rq.friction_scale();
    const auto at = [&](const int k) { return position(u1, k); };
    const auto allowed = [&](const int a, const int s) {
      return s >= first_segment && s <= last_segment && std::abs(s - a) > exclusion;
    };
    ContactContribution cc;
    cc.want_tangent = rq.want_tangent;
    for (const auto &pr : broad.candidates())
      for (const bool a_on_b : {true, false})
        {
          const int a = a_on_b ? pr.i : pr.j, seg = a_on_b ? pr.j : pr.i;
          bool listed = false;
          for (const auto &cp : segment_points[a])
            {
              const Vec2 xp = point_position(u1, cp);
              const auto &nodes = cell_node[cp.cell];
              const std::array<Vec2, 3> x{{xp, at(seg), at(seg + 1)}};
              const std::array<Vec2, 3> w0{
                  {point_velocity0(rq, cp), rq.velocity0(seg), rq.velocity0(seg + 1)}};
              double tc, fv;
              const bool touch =
                  point_stretch_contact(self_settings, 0.5 * cp.weight, x, w0, rq.friction_c_vel(),
                                        allowed(a, seg + 1), cc, tc, fv, fs);
              e.max_overlap = std::max(e.max_overlap, cc.overlap);
              if (!touch)
                continue;
              add_point_on_cell(rq, cc, cp.cell, cp.N, seg, e);
              e.friction_damping =
                  std::max(e.friction_damping, friction_damping(self_settings, cc.normal_force));
              for (std::size_t l = 0; l < nodes.size(); ++l)
                e.node_contact_force[nodes[l]] += cp.N[l] * (cc.normal_force - fv);
              e.node_contact_force[seg] += (1.0 - tc) * cc.normal_force;
              e.node_contact_force[seg + 1] += tc * cc.normal_force - fv;
              // The contact network: one pair per segment and stretch, at
              // the first point the stretch's nearest segment presses.
              if (listed ||
                  !contact::nearest_of_stretch(xp, seg, contact::closest_on_segment(xp, x[1], x[2]).distance2,
                                               at, [&](const int s) { return allowed(a, s); }))
                continue;
              listed = true;
              if (a_on_b)
                e.pairs.push_back({a, seg, cp.along, tc, cc.normal_force});
              else
                e.pairs.push_back({seg, a, tc, cp.along, cc.normal_force});
            }
        }
  }
} // namespace wirefem::fem
