#include <wirefem/contact/segment_distance.h>
#include <wirefem/discrete/terms.h>

#include <algorithm>
#include <cmath>

namespace wirefem::discrete
{
  using geometry::Vec2;

  WallContactTerm::WallContactTerm(const double radius, const ContactLaw &law)
    : radius(radius)
    , law(law)
  {
  }

  void WallContactTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    const double half_d = 0.5 * law.diameter;
    const double corner_x = std::sqrt(radius * radius - half_d * half_d);
    trial_history.clear();
    for (int k = c.first; k < c.last; ++k)
      {
        const Vec2 p = c.x[k];
        const double dist = norm(p);
        double overlap;
        Vec2 n; // unit vector from the node towards the wall
        if (std::abs(p.y) * radius < half_d * dist)
          {
            // Within an opening: the nearest wall is a corner of the mouth.
            const Vec2 corner{p.x > 0.0 ? corner_x : -corner_x, p.y > 0.0 ? half_d : -half_d};
            const Vec2 to_corner = corner - p;
            const double dc = norm(to_corner);
            overlap = half_d - dc;
            if (overlap <= 0.0)
              continue;
            n = (1.0 / dc) * to_corner;
          }
        else
          {
            overlap = dist + half_d - radius;
            if (overlap <= 0.0)
              continue;
            n = (1.0 / dist) * p;
          }
        const double fn = law.normal_stiffness * overlap;
        c.f[k] -= fn * n;
        c.contact_force[k] += fn;
        e.contact += 0.5 * law.normal_stiffness * overlap * overlap;
        e.max_penetration = std::max(e.max_penetration, overlap);
        ++e.n_wall_contacts;
        if (law.friction)
          {
            const Vec2 t = perp(n);
            const double vt = dot(c.v[k], t);
            const auto it = history.find(k);
            const auto r = contact::friction_update(
                law.coefficients, fn, vt, dt, it == history.end() ? contact::FrictionHistory{} : it->second);
            c.f[k] += r.force * t;
            e.friction_work += r.dissipated;
            e.friction_stored +=
                0.5 * law.coefficients.tangential_stiffness * r.history.elongation * r.history.elongation;
            trial_history[k] = r.history;
          }
      }
    if (law.friction)
      {
        // Nodes that left the wall release their sticking spring.
        const double kt = law.coefficients.tangential_stiffness;
        for (const auto &h : history)
          if (trial_history.find(h.first) == trial_history.end())
            e.friction_work += 0.5 * kt * h.second.elongation * h.second.elongation;
      }
  }

  void WallContactTerm::commit()
  {
    history.swap(trial_history);
  }

  SelfContactTerm::SelfContactTerm(const ContactLaw &law, const double skin, const int exclusion)
    : law(law)
    , exclusion(exclusion)
    , broad(law.diameter, skin, exclusion)
  {
  }

  void SelfContactTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    broad.update(c.x, c.first, c.last);
    active.clear();
    trial_history.clear();
    const int last_segment = c.last - 2;
    for (const auto &pair : broad.candidates())
      {
        const int i = pair.i, j = pair.j;
        const auto cp = contact::closest_points(c.x[i], c.x[i + 1], c.x[j], c.x[j + 1]);
        if (cp.distance >= law.diameter)
          continue;
        // A closest point at the far end of a segment is the near end of the
        // next one, which reports the same contact (or a closer one) - unless
        // that next pair lies inside the exclusion window.
        if ((cp.s >= 1.0 && i < last_segment && j - (i + 1) > exclusion) || (cp.t >= 1.0 && j < last_segment))
          continue;
        const double overlap = law.diameter - cp.distance;
        e.max_penetration = std::max(e.max_penetration, overlap);
        if (cp.distance < 1e-12 * law.diameter)
          continue; // centrelines cross: no normal; reported through max_penetration
        const Vec2 n = (1.0 / cp.distance) * (cp.p - cp.q); // from B towards A
        const double fn = law.normal_stiffness * overlap;
        Vec2 fa = fn * n;
        e.contact += 0.5 * law.normal_stiffness * overlap * overlap;
        if (law.friction)
          {
            const Vec2 t = perp(n);
            const Vec2 va = (1.0 - cp.s) * c.v[i] + cp.s * c.v[i + 1];
            const Vec2 vb = (1.0 - cp.t) * c.v[j] + cp.t * c.v[j + 1];
            const double vt = dot(va - vb, t);
            // A contact that slides across a node moves to the neighbouring
            // segment pair: it keeps its history.
            contact::FrictionHistory old;
            for (const auto k : {key(i, j), key(i - 1, j), key(i + 1, j), key(i, j - 1), key(i, j + 1)})
              if (const auto it = history.find(k); it != history.end() && !it->second.taken)
                {
                  old = it->second.history;
                  it->second.taken = true;
                  break;
                }
            const auto r = contact::friction_update(law.coefficients, fn, vt, dt, old);
            fa += r.force * t;
            e.friction_work += r.dissipated;
            e.friction_stored +=
                0.5 * law.coefficients.tangential_stiffness * r.history.elongation * r.history.elongation;
            trial_history[key(i, j)] = {r.history, false};
          }
        c.f[i] += (1.0 - cp.s) * fa;
        c.f[i + 1] += cp.s * fa;
        c.f[j] -= (1.0 - cp.t) * fa;
        c.f[j + 1] -= cp.t * fa;
        c.contact_force[i] += (1.0 - cp.s) * fn;
        c.contact_force[i + 1] += cp.s * fn;
        c.contact_force[j] += (1.0 - cp.t) * fn;
        c.contact_force[j + 1] += cp.t * fn;
        active.push_back({i, j, cp.s, cp.t, fn});
      }
    e.n_self_contacts += static_cast<int>(active.size());
    // Pairs that separated (or whose history no current pair took) release
    // their sticking spring: that energy is dissipated.
    const double kt = law.coefficients.tangential_stiffness;
    for (auto &h : history)
      {
        if (!h.second.taken)
          e.friction_work += 0.5 * kt * h.second.history.elongation * h.second.history.elongation;
        h.second.taken = false; // add_forces may be evaluated again before commit
      }
  }

  void SelfContactTerm::commit()
  {
    history.swap(trial_history);
  }
} // namespace wirefem::discrete

#include <wirefem/io/binary.h>

namespace wirefem::discrete
{
  void WallContactTerm::save(std::ostream &out) const
  {
    io::write_map(out, history);
  }

  void WallContactTerm::load(std::istream &in)
  {
    io::read_map(in, history);
  }

  void SelfContactTerm::save(std::ostream &out) const
  {
    io::write_map(out, history);
  }

  void SelfContactTerm::load(std::istream &in)
  {
    io::read_map(in, history);
    broad.invalidate();
  }
} // namespace wirefem::discrete
