#include <wirefem/contact/segment_distance.h>
#include <wirefem/discrete/terms.h>
#include <wirefem/injection/channels.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace wirefem::discrete
{
  using core::Vec2;

  void FrictionWork::begin(const Chain &c)
  {
    std::fill(force.trial.begin() + c.first, force.trial.begin() + c.last, Vec2{});
    stored_trial = 0.0;
  }

  double FrictionWork::dissipated(const Chain &c, const double dt) const
  {
    double work = 0.0; // done on the wire
    for (int k = c.first; k < c.last; ++k)
      work += 0.5 * dot(force.committed[k] + force.trial[k], c.v[k]) * dt;
    return -work - (stored_trial - stored);
  }

  void FrictionWork::save(std::ostream &out) const
  {
    force.save(out);
    core::write_raw(out, stored);
  }

  void FrictionWork::load(std::istream &in)
  {
    force.load(in);
    stored = stored_trial = core::read_raw<double>(in);
  }

  double segment_rotation_rate(const Chain &c, const int a)
  {
    const Vec2 r = c.x[a + 1] - c.x[a];
    return cross(r, c.v[a + 1] - c.v[a]) / dot(r, r);
  }

  double node_rotation_rate(const Chain &c, const int k)
  {
    assert(c.last - c.first >= 2);
    const bool left = k - 1 >= c.first, right = k + 1 < c.last;
    if (left && right)
      return 0.5 * (segment_rotation_rate(c, k - 1) + segment_rotation_rate(c, k));
    return left ? segment_rotation_rate(c, k - 1) : segment_rotation_rate(c, k);
  }

  int segment_moment_forces(const Chain &c, const int a, const double moment, NodalForce *out)
  {
    // The segment's angle phi has d phi / d x_{a+1} = perp(r) / |r|^2 = -d phi / d x_a.
    const Vec2 r = c.x[a + 1] - c.x[a];
    const Vec2 g = (moment / dot(r, r)) * perp(r);
    out[0] = {a + 1, g};
    out[1] = {a, -1.0 * g};
    return 2;
  }

  int node_moment_forces(const Chain &c, const int k, const double moment, NodalForce *out)
  {
    const bool left = k - 1 >= c.first, right = k + 1 < c.last;
    const double share = left && right ? 0.5 * moment : moment;
    int n = 0;
    if (left)
      n += segment_moment_forces(c, k - 1, share, out + n);
    if (right)
      n += segment_moment_forces(c, k, share, out + n);
    return n;
  }

  namespace
  {
    /// Applies the nodal forces of a friction moment and books them as friction.
    void apply_friction_moment(Chain &c, FrictionWork &work, const NodalForce *forces, const int n)
    {
      for (int i = 0; i < n; ++i)
        {
          c.f[forces[i].node] += forces[i].force;
          work.add_force(forces[i].node, forces[i].force);
        }
    }

    void require_capacity(const ContactLaw &law, const int capacity, const char *term)
    {
      if (law.friction && capacity <= 0)
        throw std::invalid_argument(std::string(term) + ": friction needs the chain capacity");
    }
  } // namespace

  namespace
  {
    /// A contact kind's share of the stability limit. The two kinds
    /// together allow 4 k_n/m, a node in two contacts with a margin of 2
    /// that also holds their sticking springs (k_t <= k_n), so the step does
    /// not depend on whether friction is on: a neutral effect must not
    /// change the trajectory. Friction at the surface turns the wire too: a
    /// contact's slip then also moves with the nodes next to it (d/2 times
    /// the turning of a node and of a segment), and the squared norm of its
    /// gradient, at most 2 without, is at most (sqrt 2 + 0.94 d/lambda_0)^2:
    /// a sticking spring adds k_t ((sqrt 2 + d/lambda_0)^2 - 2)/m. That
    /// option is not a neutral effect, so the step may change with it.
    StabilityBound contact_bound(const ContactLaw &law, const double mass, const double lambda0)
    {
      StabilityBound b{2.0 * law.normal_stiffness / mass, 0.0};
      if (law.friction && law.surface_torque)
        {
          const double arm = std::sqrt(2.0) + law.diameter / lambda0;
          b.omega2 += law.coefficients.tangential_stiffness * (arm * arm - 2.0) / mass;
        }
      return b;
    }
  } // namespace

  StabilityBound WallContactTerm::stability_bound(const double mass, const double lambda0) const
  {
    return contact_bound(law, mass, lambda0);
  }

  StabilityBound SelfContactTerm::stability_bound(const double mass, const double lambda0) const
  {
    return contact_bound(law, mass, lambda0);
  }

  StabilityBound ChannelTerm::stability_bound(const double mass, const double lambda0) const
  {
    return {2.0 * stiffness * lambda0 / mass, 0.0};
  }

  WallContactTerm::WallContactTerm(const double radius, const ContactLaw &law, const int capacity)
    : radius(radius)
    , law(law)
  {
    require_capacity(law, capacity, "WallContactTerm");
    if (law.friction)
      friction_work.resize(capacity);
  }

  bool WallContactTerm::touch_circle(const Vec2 &p, const double half_d, const double corner_x,
                                     double &overlap, Vec2 &n) const
  {
    const double dist = norm(p);
    if (!tangential && std::abs(p.y) * radius < half_d * dist)
      {
        // Within an opening: the nearest wall is a corner of the mouth.
        return injection::touch_corner({p.x > 0.0 ? corner_x : -corner_x, p.y > 0.0 ? half_d : -half_d}, p,
                                       half_d, overlap, n);
      }
    overlap = dist + half_d - radius;
    if (overlap <= 0.0)
      return false;
    n = (1.0 / dist) * p;
    return true;
  }

  bool WallContactTerm::touch_shaped(const Vec2 &p, const double half_d, double &overlap, Vec2 &n) const
  {
    injection::WallTouch touch;
    if (!shaped->touch(p, half_d, touch))
      return false;
    overlap = touch.overlap;
    n = touch.towards;
    return true;
  }

  void WallContactTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    const double half_d = 0.5 * law.diameter;
    const double corner_x = std::sqrt(radius * radius - half_d * half_d);
    trial_history.clear();
    if (law.friction)
      friction_work.begin(c);
    // Tangential channels: the wire still in them is the channels', and
    // the wall has no radial mouths.
    const auto [left_end, right_begin] =
        tangential ? injection::nodes_past_tangential_inlets(c.first, c.last, [&](int k) { return c.x[k].y; })
                   : std::pair{c.first, c.last};
    for (int k = left_end; k < right_begin; ++k)
      {
        double overlap;
        Vec2 n; // unit vector from the node towards the wall
        if (!(shaped ? touch_shaped(c.x[k], half_d, overlap, n)
                     : touch_circle(c.x[k], half_d, corner_x, overlap, n)))
          continue;
        const double fn = law.normal_stiffness * overlap;
        c.f[k] -= fn * n;
        c.contact_force[k] += fn;
        e.contact += 0.5 * law.normal_stiffness * overlap * overlap;
        e.max_penetration = std::max(e.max_penetration, overlap);
        ++e.n_wall_contacts;
        if (law.friction)
          {
            const Vec2 t = perp(n);
            // At the surface (arm d/2 along n) the node's rotation adds to
            // the slip, and the friction force turns the node.
            const double vt =
                law.surface_torque ? dot(c.v[k], t) + half_d * node_rotation_rate(c, k) : dot(c.v[k], t);
            const auto it = history.find(k);
            const auto r = contact::friction_update(
                law.coefficients, fn, vt, dt, it == history.end() ? contact::FrictionHistory{} : it->second);
            c.f[k] += r.force * t;
            friction_work.add_force(k, r.force * t);
            if (law.surface_torque)
              {
                NodalForce forces[4];
                apply_friction_moment(c, friction_work, forces,
                                      node_moment_forces(c, k, half_d * r.force, forces));
              }
            const double stored =
                0.5 * law.coefficients.tangential_stiffness * r.history.elongation * r.history.elongation;
            e.friction_stored += stored;
            friction_work.add_stored(stored);
            trial_history[k] = r.history;
          }
      }
    // Nodes that left the wall released their sticking spring: its energy
    // is no longer stored, so it counts as dissipated.
    if (law.friction)
      e.friction_work += friction_work.dissipated(c, dt);
  }

  void WallContactTerm::commit()
  {
    history.swap(trial_history);
    if (law.friction)
      friction_work.commit();
  }

  SelfContactTerm::SelfContactTerm(const ContactLaw &law, const double skin, const int exclusion,
                                   const int capacity)
    : law(law)
    , exclusion(exclusion)
    , broad(law.diameter, skin, exclusion)
  {
    require_capacity(law, capacity, "SelfContactTerm");
    if (law.friction)
      friction_work.resize(capacity);
  }

  core::Vec2 SelfContactTerm::friction_force(Chain &c, const int k, const int m, const double t, const Vec2 n,
                                             const double fn, const double dt, StepEnergy &e)
  {
    // The friction of the contact of node k with segment m (at t, normal n,
    // normal force fn): its force on the node, its history and its work.
    const Vec2 tangent = perp(n);
    const Vec2 vq = (1.0 - t) * c.v[m] + t * c.v[m + 1];
    // At the surfaces (arms d/2 against n on the node's side,
    // along n on the segment's) both wires' rotations add to the slip.
    const double half_d = 0.5 * law.diameter;
    const double vt =
        dot(c.v[k] - vq, tangent) -
        (law.surface_torque ? half_d * (node_rotation_rate(c, k) + segment_rotation_rate(c, m)) : 0.0);
    // A node that slides across a node of the other wire moves on
    // to the neighbouring segment: it keeps its history.
    contact::FrictionHistory old;
    for (const auto kk : {key(k, m), key(k, m - 1), key(k, m + 1)})
      if (const auto it = history.find(kk); it != history.end() && !it->second.taken)
        {
          old = it->second.history;
          it->second.taken = true;
          break;
        }
    const auto r = contact::friction_update(law.coefficients, fn, vt, dt, old);
    const Vec2 ft = r.force * tangent;
    friction_work.add_force(k, ft);
    friction_work.add_force(m, -(1.0 - t) * ft);
    friction_work.add_force(m + 1, -t * ft);
    if (law.surface_torque)
      {
        // Both surfaces get the moment -d/2 F_t of the friction force at their arms.
        NodalForce forces[6];
        int nf = node_moment_forces(c, k, -half_d * r.force, forces);
        nf += segment_moment_forces(c, m, -half_d * r.force, forces + nf);
        apply_friction_moment(c, friction_work, forces, nf);
      }
    const double stored =
        0.5 * law.coefficients.tangential_stiffness * r.history.elongation * r.history.elongation;
    e.friction_stored += stored;
    friction_work.add_stored(stored);
    trial_history[key(k, m)] = {r.history, false};
    return ft;
  }

  void SelfContactTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    broad.update(c.x, c.first, c.last);
    active.clear();
    trial_history.clear();
    if (law.friction)
      friction_work.begin(c);
    const int first_segment = c.first, last_segment = c.last - 2;
    // Node k may touch segment m when the segment's nearer node is more than
    // the exclusion window away along the wire (the same for m < k and m > k).
    const auto allowed = [&](const int k, const int m) {
      return m >= first_segment && m <= last_segment && (m > k ? m - k : k - m - 1) > exclusion;
    };
    const double d2 = law.diameter * law.diameter;
    for (const auto &pair : broad.candidates())
      {
        // Most candidates are apart by more than d; their boxes say so cheaply
        // (with a margin far above rounding, so no contact is ever skipped).
        if (contact::box_gap(c.x[pair.i], c.x[pair.i + 1], c.x[pair.j], c.x[pair.j + 1]) >
            (1.0 + 1e-9) * law.diameter)
          continue;
        // The first node of each segment of a candidate pair against the
        // other segment (and the chain's last node, which begins no
        // segment), so every node meets every segment near it exactly once.
        for (int which = 0; which < 3; ++which)
          {
            const int k = which == 0 ? pair.i : which == 1 ? pair.j : pair.j + 1;
            const int m = which == 0 ? pair.j : pair.i;
            if ((which == 2 && pair.j != last_segment) || !allowed(k, m))
              continue;
            const Vec2 p = c.x[k];
            const auto cp = contact::closest_on_segment(p, c.x[m], c.x[m + 1]);
            if (cp.distance2 >= d2 || !contact::nearest_of_stretch(
                                          p, m, cp.distance2, [&](const int n) { return c.x[n]; },
                                          [&](const int n) { return allowed(k, n); }))
              continue;
            const double distance = std::sqrt(cp.distance2);
            const double overlap = law.diameter - distance;
            e.max_penetration = std::max(e.max_penetration, overlap);
            if (distance < 1e-12 * law.diameter)
              continue; // centrelines cross: no normal; reported through max_penetration
            const double t = cp.t;
            const Vec2 n = (1.0 / distance) * (p - cp.q); // from the segment towards the node
            const double fn = law.normal_stiffness * overlap;
            Vec2 f = fn * n;
            e.contact += 0.5 * law.normal_stiffness * overlap * overlap;
            if (law.friction)
              f += friction_force(c, k, m, t, n, fn, dt, e);
            c.f[k] += f;
            c.f[m] -= (1.0 - t) * f;
            c.f[m + 1] -= t * f;
            c.contact_force[k] += fn;
            c.contact_force[m] += (1.0 - t) * fn;
            c.contact_force[m + 1] += t * fn;
            if (which == 0)
              active.push_back({k, m, 0.0, t, fn});
            else if (which == 1)
              active.push_back({m, k, t, 0.0, fn});
            else
              active.push_back({m, k - 1, t, 1.0, fn}); // the last node ends segment k - 1
          }
      }
    e.n_self_contacts += static_cast<int>(active.size());
    // Pairs that separated (or whose history no current pair took) released
    // their sticking spring: its energy is no longer stored, so it counts as
    // dissipated.
    if (law.friction)
      e.friction_work += friction_work.dissipated(c, dt);
    for (auto &h : history)
      h.second.taken = false; // add_forces may be evaluated again before commit
  }

  void SelfContactTerm::commit()
  {
    history.swap(trial_history);
    if (law.friction)
      friction_work.commit();
  }
} // namespace wirefem::discrete

#include <wirefem/core/binary.h>

namespace wirefem::discrete
{
  namespace
  {
    /// A contact term's restart data: its friction histories and, with
    /// friction, the work friction has done.
    template <typename Histories>
    void save_contact_state(std::ostream &out, const Histories &history, const bool friction,
                            const FrictionWork &work)
    {
      core::write_map(out, history);
      if (friction)
        work.save(out);
    }

    template <typename Histories>
    void load_contact_state(std::istream &in, Histories &history, const bool friction, FrictionWork &work)
    {
      core::read_map(in, history);
      if (friction)
        work.load(in);
    }
  } // namespace

  void WallContactTerm::save(std::ostream &out) const
  {
    save_contact_state(out, history, law.friction, friction_work);
  }

  void WallContactTerm::load(std::istream &in)
  {
    load_contact_state(in, history, law.friction, friction_work);
  }

  void SelfContactTerm::save(std::ostream &out) const
  {
    save_contact_state(out, history, law.friction, friction_work);
  }

  void SelfContactTerm::load(std::istream &in)
  {
    load_contact_state(in, history, law.friction, friction_work);
    broad.invalidate();
  }
} // namespace wirefem::discrete

namespace wirefem::discrete
{
  bool ChannelTerm::add_segment(Chain &c, const int a, const int b, const injection::Side side,
                                StepEnergy &e) const
  {
    // s past the mouth along the cut's normal m (the axis for the paper's
    // channels), y across the axis.
    const Vec2 m = channels.cut_normal(side), n = perp(channels.axis(side)),
               origin = channels.cut_origin(side);
    const Vec2 ra = c.x[a] - origin, rb = c.x[b] - origin;
    const double sa = dot(ra, m), sb = dot(rb, m);
    if (sa >= 0.0 && sb >= 0.0)
      return false;
    const double ya = dot(ra, n), yb = dot(rb, n);
    // The part inside, t in [t0, t1] of y(t) = ya + (yb - ya) t, and the
    // derivatives of its ends with respect to sa and sb.
    double t0 = 0.0, t1 = 1.0;
    double dt0_dsa = 0.0, dt0_dsb = 0.0, dt1_dsa = 0.0, dt1_dsb = 0.0;
    if (sa < 0.0 && sb >= 0.0)
      {
        const double q = sa - sb;
        t1 = sa / q;
        dt1_dsa = -sb / (q * q);
        dt1_dsb = sa / (q * q);
      }
    else if (sa >= 0.0 && sb < 0.0)
      {
        const double q = sa - sb;
        t0 = sa / q;
        dt0_dsa = -sb / (q * q);
        dt0_dsb = sa / (q * q);
      }
    // I = int_{t0}^{t1} y^2 dt and its derivatives in ya, yb: two-point
    // Gauss is exact for these cubics.
    const double len = t1 - t0, g = 0.5 / std::sqrt(3.0);
    double integral = 0.0, di_dya = 0.0, di_dyb = 0.0;
    for (const double tq : {t0 + (0.5 - g) * len, t0 + (0.5 + g) * len})
      {
        const double y = ya + (yb - ya) * tq;
        integral += 0.5 * len * y * y;
        di_dya += len * y * (1.0 - tq);
        di_dyb += len * y * tq;
      }
    const double y0 = ya + (yb - ya) * t0, y1 = ya + (yb - ya) * t1;
    const double di_dsa = y1 * y1 * dt1_dsa - y0 * y0 * dt0_dsa;
    const double di_dsb = y1 * y1 * dt1_dsb - y0 * y0 * dt0_dsb;
    const double w = 0.5 * stiffness * c.lambda0;
    e.contact += w * integral;
    c.f[a] -= w * (di_dya * n + di_dsa * m);
    c.f[b] -= w * (di_dyb * n + di_dsb * m);
    if (sa < 0.0)
      e.max_penetration = std::max(e.max_penetration, std::abs(ya));
    if (sb < 0.0)
      e.max_penetration = std::max(e.max_penetration, std::abs(yb));
    return true;
  }

  void ChannelTerm::add_forces(Chain &c, double, StepEnergy &e)
  {
    // From each end inwards, up to the first segment wholly inside the cavity.
    for (int k = c.first; k + 1 < c.last; ++k)
      if (!add_segment(c, k, k + 1, injection::Side::left, e))
        break;
    for (int k = c.last - 1; channels.pushes(injection::Side::right) && k - 1 >= c.first; --k)
      if (!add_segment(c, k - 1, k, injection::Side::right, e))
        break;
  }
} // namespace wirefem::discrete
