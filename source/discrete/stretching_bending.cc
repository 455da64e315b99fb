#include <wirefem/discrete/terms.h>

#include <cmath>
#include <stdexcept>

namespace wirefem::discrete
{
  using core::Vec2;

  namespace
  {
    /// The turning angle zeta at node k and its gradients with respect to
    /// x_{k-1}, x_k, x_{k+1}: zeta = angle(b) - angle(a) with a, b the
    /// segments before and after, and d angle(u)/du = perp(u)/|u|^2.
    struct TurningAngle
    {
      Vec2 a, b;
      double zeta;

      TurningAngle(const Chain &c, const int k)
        : a(c.x[k] - c.x[k - 1])
        , b(c.x[k + 1] - c.x[k])
        , zeta(std::atan2(cross(a, b), dot(a, b)))
      {
      }

      Vec2 g_prev() const { return (1.0 / norm_square(a)) * perp(a); }
      Vec2 g_next() const { return (1.0 / norm_square(b)) * perp(b); }

      /// d zeta/dt from the velocities of the three nodes.
      double rate(const Chain &c, const int k) const
      {
        const Vec2 gp = g_prev(), gn = g_next();
        return dot(gp, c.v[k - 1] - c.v[k]) + dot(gn, c.v[k + 1] - c.v[k]);
      }

      /// Adds the forces -moment * d zeta/dx.
      void apply(Chain &c, const int k, const double moment) const
      {
        const Vec2 gp = g_prev(), gn = g_next();
        c.f[k - 1] -= moment * gp;
        c.f[k] += moment * (gp + gn);
        c.f[k + 1] -= moment * gn;
      }
    };
  } // namespace

  StabilityBound StretchingTerm::stability_bound(const double mass, const double) const
  {
    return {4.0 * k1 / mass, 4.0 * damping / mass};
  }

  StabilityBound BendingTerm::stability_bound(const double mass, const double lambda0) const
  {
    const double scale = 16.0 / (mass * lambda0 * lambda0);
    return {scale * law.elastic_stiffness(), scale * damping};
  }

  StabilityBound CurvatureLimitTerm::stability_bound(const double mass, const double lambda0) const
  {
    return {16.0 * stiffness / (mass * lambda0 * lambda0), 0.0};
  }

  StabilityBound DampingTerm::stability_bound(const double, const double) const
  {
    return {0.0, gamma};
  }

  StretchingTerm::StretchingTerm(const double k1, const double axial_damping, const int capacity)
    : k1(k1)
    , damping(axial_damping)
  {
    if (damping > 0.0)
      {
        if (capacity <= 0)
          throw std::invalid_argument("StretchingTerm: a dashpot needs the chain capacity");
        previous.resize(capacity);
      }
  }

  void StretchingTerm::commit()
  {
    if (!previous.empty())
      previous.commit();
  }

  void StretchingTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    for (int k = c.first; k < c.last - 1; ++k)
      {
        const Vec2 d = c.x[k + 1] - c.x[k];
        const double len = norm(d);
        const double stretch = len - c.lambda0;
        double tension = k1 * stretch;
        if (damping > 0.0)
          {
            const double rate = dot(c.v[k + 1] - c.v[k], d) / len;
            tension += damping * rate;
            e.damping_work += damping * 0.5 * (previous.committed[k] + rate) * rate * dt;
            previous.trial[k] = rate;
          }
        const Vec2 fk = (tension / len) * d; // pulls k towards k+1 when stretched
        c.f[k] += fk;
        c.f[k + 1] -= fk;
        e.stretching += 0.5 * k1 * stretch * stretch;
      }
  }

  BendingTerm::BendingTerm(const material::MomentCurvatureLaw &law, const double rotational_damping,
                           const int capacity)
    : law(law)
    , damping(rotational_damping)
  {
    if (law.is_plastic())
      {
        state.resize(capacity);
        trial_state.resize(capacity);
      }
    if (damping > 0.0)
      previous.resize(capacity);
  }

  double BendingTerm::turning_angle(const Chain &c, const int k)
  {
    return TurningAngle(c, k).zeta;
  }

  void BendingTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    const bool plastic = !state.empty();
    for (int k = c.first + 1; k < c.last - 1; ++k)
      {
        const TurningAngle angle(c, k);
        const double zeta = angle.zeta;
        double moment = plastic ? spring_moment(law, zeta, &state[k], &trial_state[k], e)
                                : spring_moment(law, zeta, nullptr, nullptr, e);
        if (damping > 0.0)
          {
            const double rate = angle.rate(c, k);
            moment += damping * rate;
            e.damping_work += damping * 0.5 * (previous.committed[k] + rate) * rate * dt;
            previous.trial[k] = rate;
          }
        angle.apply(c, k, moment);
      }
  }

  double spring_moment(const material::MomentCurvatureLaw &law, const double zeta,
                       const material::PlasticState *old, material::PlasticState *trial, StepEnergy &e)
  {
    if (!law.is_plastic())
      {
        const double moment = law.elastic_stiffness() * zeta;
        e.bending += 0.5 * moment * zeta;
        return moment;
      }
    const auto r = law.evaluate(zeta, *old);
    *trial = r.state;
    e.plastic_work += r.plastic_work;
    e.bending += law.elastic_energy(zeta, r.state);
    return r.moment;
  }

  void BendingTerm::commit()
  {
    // No copy needed: add_forces writes the trial state of every interior
    // node, and nodes that are not interior yet hold zero state in both.
    state.swap(trial_state);
    if (!previous.empty())
      previous.commit();
  }

  void CurvatureLimitTerm::add_forces(Chain &c, double, StepEnergy &e)
  {
    // |zeta| is the angle between the segments, so |zeta| <= zeta_max while
    // a.b >= cos(zeta_max) |a| |b|: that test (with a margin far above
    // rounding) spares the atan2 at almost every node.
    const double cos_max = std::cos(zeta_max);
    for (int k = c.first + 1; k < c.last - 1; ++k)
      {
        const Vec2 a = c.x[k] - c.x[k - 1], b = c.x[k + 1] - c.x[k];
        const double ab = std::sqrt(norm_square(a) * norm_square(b));
        if (dot(a, b) - cos_max * ab > 1e-9 * ab)
          continue;
        const TurningAngle angle(c, k);
        const double excess = std::abs(angle.zeta) - zeta_max;
        if (excess <= 0.0)
          continue;
        angle.apply(c, k, (angle.zeta > 0.0 ? 1.0 : -1.0) * stiffness * excess);
        e.contact += 0.5 * stiffness * excess * excess;
      }
  }

  DampingTerm::DampingTerm(const double gamma, const int capacity)
    : gamma(gamma)
  {
    previous.resize(capacity);
  }

  void DampingTerm::commit()
  {
    previous.commit();
  }

  void DampingTerm::add_forces(Chain &c, const double dt, StepEnergy &e)
  {
    const double cm = gamma * c.node_mass;
    for (int i = 0; i < c.n_prescribed; ++i)
      previous.trial[c.first + i] = Vec2{}; // no damping there
    for (int i = 0; i < c.n_prescribed_last; ++i)
      previous.trial[c.last - 1 - i] = Vec2{};
    for (int k = c.first + c.n_prescribed; k < c.last - c.n_prescribed_last; ++k)
      {
        c.f[k] -= cm * c.v[k];
        e.damping_work += cm * 0.5 * dot(previous.committed[k] + c.v[k], c.v[k]) * dt;
        previous.trial[k] = c.v[k];
      }
  }
} // namespace wirefem::discrete

#include <wirefem/core/binary.h>

namespace wirefem::discrete
{
  void BendingTerm::save(std::ostream &out) const
  {
    core::write_vector(out, state, 0, state.size());
    previous.save(out);
  }

  void BendingTerm::load(std::istream &in)
  {
    core::read_vector(in, state);
    trial_state = state;
    previous.load(in);
  }

  void StretchingTerm::save(std::ostream &out) const
  {
    previous.save(out);
  }

  void StretchingTerm::load(std::istream &in)
  {
    previous.load(in);
  }

  void DampingTerm::save(std::ostream &out) const
  {
    previous.save(out);
  }

  void DampingTerm::load(std::istream &in)
  {
    previous.load(in);
  }
} // namespace wirefem::discrete
