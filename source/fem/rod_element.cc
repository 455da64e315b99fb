#include <wirefem/fem/rod_element.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>

#include <Sacado.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace wirefem::fem
{
  ElementShape ElementShape::lagrange(const unsigned int degree, const double h, const unsigned int n_q)
  {
    if (degree < 1 || degree > max_degree || n_q < 1 || n_q > max_points || !(h > 0.0))
      throw std::invalid_argument("ElementShape: 1 <= degree <= 3, 1 <= n_q <= 8 and h > 0 required");
    const dealii::FE_Q<1> fe(degree);
    const dealii::QGauss<1> quadrature(n_q);
    ElementShape s;
    s.n_nodes = fe.dofs_per_cell;
    s.n_q = n_q;
    s.length = h;
    s.N.resize(n_q * s.n_nodes);
    s.dN.resize(n_q * s.n_nodes);
    for (unsigned int q = 0; q < n_q; ++q)
      {
        s.weight.push_back(quadrature.weight(q) * h);
        for (unsigned int a = 0; a < s.n_nodes; ++a)
          {
            s.N[q * s.n_nodes + a] = fe.shape_value(a, quadrature.point(q));
            s.dN[q * s.n_nodes + a] = fe.shape_grad(a, quadrature.point(q))[0] / h;
          }
      }
    for (unsigned int a = 0; a < s.n_nodes; ++a)
      s.node_position.push_back(fe.get_unit_support_points()[a][0]);
    return s;
  }

  void lagrange_basis(const std::vector<double> &pos, const double xi, double *N, double *dN)
  {
    const std::size_t nn = pos.size();
    for (std::size_t a = 0; a < nn; ++a)
      {
        N[a] = 1.0;
        dN[a] = 0.0;
        for (std::size_t b = 0; b < nn; ++b)
          if (b != a)
            {
              const double f = 1.0 / (pos[a] - pos[b]);
              dN[a] = dN[a] * (xi - pos[b]) * f + N[a] * f;
              N[a] *= (xi - pos[b]) * f;
            }
      }
  }

  namespace
  {
    using std::cos;
    using std::sin;

    struct Strains
    {
      double eps, gamma, kappa, theta;
    };

    template <typename T>
    struct PointKinematics
    {
      T dx, dy, theta, kappa, c, s, eps, gamma;
    };

    template <typename T>
    PointKinematics<T> kinematics(const ElementShape &shape, const unsigned int q, const T *u)
    {
      PointKinematics<T> k{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      for (unsigned int a = 0; a < shape.n_nodes; ++a)
        {
          const double N = shape.value(q, a), dN = shape.derivative(q, a);
          k.dx += dN * u[3 * a];
          k.dy += dN * u[3 * a + 1];
          k.theta += N * u[3 * a + 2];
          k.kappa += dN * u[3 * a + 2];
        }
      k.c = cos(k.theta);
      k.s = sin(k.theta);
      k.eps = k.c * k.dx + k.s * k.dy - 1.0;
      k.gamma = -k.s * k.dx + k.c * k.dy;
      return k;
    }

    /// What the tangent needs of a quadrature point, kept from the residual.
    struct PointEvaluation
    {
      PointKinematics<double> k;
      material::MomentResult m;
    };

    // Residual with scalar type T: double for the value, Fad for the tangent
    // (points, if given, receives each quadrature point's kinematics and
    // law, so that the tangent does not evaluate them again.)
    template <typename T>
    void residual(const ElementShape &shape, const SectionProperties &section,
                  const material::MomentCurvatureLaw &law, const T *u, const PointState *old, const double dt,
                  const double viscous_scale, T *r, ElementResult *values, PointEvaluation *points = nullptr)
    {
      const unsigned int n = 3 * shape.n_nodes;
      for (unsigned int i = 0; i < n; ++i)
        r[i] = 0.0;
      for (unsigned int q = 0; q < shape.n_q; ++q)
        {
          const auto k = kinematics(shape, q, u);
          const double kappa_value = Sacado::ScalarValue<T>::eval(k.kappa);
          const auto m = law.evaluate(kappa_value, old[q].plastic);
          if constexpr (std::is_same_v<T, double>)
            if (points)
              points[q] = {k, m};
          // Linearisation of the return mapping at the current curvature.
          T M = m.moment + m.tangent * (k.kappa - kappa_value);
          T N = section.EA * k.eps;
          const T Q = section.GA * k.gamma;
          const double w = shape.weight[q];
          T Nv = 0.0, Mv = 0.0;
          if (dt > 0.0)
            {
              Nv = section.axial_viscosity / dt * (k.eps - old[q].axial_strain);
              Mv = section.bending_viscosity / dt * (k.kappa - old[q].curvature);
              N += viscous_scale * Nv;
              M += viscous_scale * Mv;
            }
          for (unsigned int a = 0; a < shape.n_nodes; ++a)
            {
              const double Na = shape.value(q, a), dNa = shape.derivative(q, a);
              r[3 * a] += w * (N * k.c - Q * k.s) * dNa;
              r[3 * a + 1] += w * (N * k.s + Q * k.c) * dNa;
              r[3 * a + 2] += w * ((N * k.gamma - Q * (1.0 + k.eps)) * Na + M * dNa);
              if (values && dt > 0.0)
                {
                  // The viscous part alone (values are doubles here).
                  const double nv = Sacado::ScalarValue<T>::eval(Nv), mv = Sacado::ScalarValue<T>::eval(Mv);
                  const double c = Sacado::ScalarValue<T>::eval(k.c), sn = Sacado::ScalarValue<T>::eval(k.s);
                  const double g = Sacado::ScalarValue<T>::eval(k.gamma);
                  values->viscous_residual[3 * a] += w * nv * c * dNa;
                  values->viscous_residual[3 * a + 1] += w * nv * sn * dNa;
                  values->viscous_residual[3 * a + 2] += w * (nv * g * Na + mv * dNa);
                }
            }
          if (values)
            {
              const double eps = Sacado::ScalarValue<T>::eval(k.eps);
              const double gamma = Sacado::ScalarValue<T>::eval(k.gamma);
              auto &st = values->state[q];
              st.plastic = m.state;
              st.axial_strain = eps;
              st.shear_strain = gamma;
              st.curvature = kappa_value;
              values->axial_energy += w * 0.5 * section.EA * eps * eps;
              values->shear_energy += w * 0.5 * section.GA * gamma * gamma;
              values->bending_energy += w * law.elastic_energy(kappa_value, m.state);
              values->plastic_work += w * m.plastic_work;
            }
        }
    }

    /// The derivative of the residual (viscous part weighted by
    /// viscous_scale), derived by hand. With the strain operators
    /// B_eps = d eps / du, B_gamma = d gamma / du, B_kappa = d kappa / du:
    ///   K = sum_q w [ N' B_eps B_eps^T + GA B_gamma B_gamma^T + M' B_kappa B_kappa^T
    ///                 + N d B_eps / du + Q d B_gamma / du ]
    /// with N' = EA + viscous_scale eta_a / dt, M' the law's algorithmic
    /// tangent + viscous_scale eta_b / dt, and the geometric terms from
    /// d (c, s) / d theta and d eps / d theta = gamma N_a, d gamma / d theta = -(1 + eps) N_a.
    void tangent(const ElementShape &shape, const SectionProperties &section, const PointEvaluation *points,
                 const PointState *old, const double dt, const double viscous_scale, double *K)
    {
      const unsigned int nn = shape.n_nodes, n = 3 * nn;
      std::fill(K, K + n * n, 0.0);
      double be[12], bg[12], bk[12];
      for (unsigned int q = 0; q < shape.n_q; ++q)
        {
          const auto &k = points[q].k;
          const auto &m = points[q].m;
          double N = section.EA * k.eps, dN = section.EA, dM = m.tangent;
          const double Q = section.GA * k.gamma;
          if (dt > 0.0)
            {
              N += viscous_scale * section.axial_viscosity / dt * (k.eps - old[q].axial_strain);
              dN += viscous_scale * section.axial_viscosity / dt;
              dM += viscous_scale * section.bending_viscosity / dt;
            }
          for (unsigned int a = 0; a < nn; ++a)
            {
              const double Na = shape.value(q, a), dNa = shape.derivative(q, a);
              be[3 * a] = k.c * dNa, be[3 * a + 1] = k.s * dNa, be[3 * a + 2] = k.gamma * Na;
              bg[3 * a] = -k.s * dNa, bg[3 * a + 1] = k.c * dNa, bg[3 * a + 2] = -(1.0 + k.eps) * Na;
              bk[3 * a] = 0.0, bk[3 * a + 1] = 0.0, bk[3 * a + 2] = dNa;
            }
          const double w = shape.weight[q];
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              K[i * n + j] += w * (dN * be[i] * be[j] + section.GA * bg[i] * bg[j] + dM * bk[i] * bk[j]);
          // Geometric part: d B_eps / du and d B_gamma / du.
          for (unsigned int a = 0; a < nn; ++a)
            {
              const double Na = shape.value(q, a), dNa = shape.derivative(q, a);
              for (unsigned int b = 0; b < nn; ++b)
                {
                  const double Nb = shape.value(q, b);
                  const double xy = w * dNa * Nb; // (x_a or y_a, theta_b) and its transpose
                  const double gx = -(N * k.s + Q * k.c) * xy, gy = (N * k.c - Q * k.s) * xy;
                  K[(3 * a) * n + 3 * b + 2] += gx;
                  K[(3 * b + 2) * n + 3 * a] += gx;
                  K[(3 * a + 1) * n + 3 * b + 2] += gy;
                  K[(3 * b + 2) * n + 3 * a + 1] += gy;
                  K[(3 * a + 2) * n + 3 * b + 2] -= w * (N * (1.0 + k.eps) + Q * k.gamma) * Na * Nb;
                }
            }
        }
    }
  } // namespace

  void evaluate_rod_element(const ElementShape &shape, const SectionProperties &section,
                            const material::MomentCurvatureLaw &law, const double *dofs,
                            const PointState *old, const double dt, const bool want_tangent,
                            ElementResult &out, const double viscous_scale)
  {
    const unsigned int n = 3 * shape.n_nodes;
    out.residual.resize(n);              // residual() clears it
    out.viscous_residual.assign(n, 0.0); // residual() adds to it
    out.state.resize(shape.n_q);         // residual() sets every field
    out.axial_energy = out.shear_energy = out.bending_energy = out.plastic_work = 0.0;
    std::array<PointEvaluation, ElementShape::max_points> points;
    residual<double>(shape, section, law, dofs, old, dt, 1.0, out.residual.data(), &out, points.data());
    if (!want_tangent)
      {
        out.tangent.clear();
        return;
      }
    out.tangent.resize(n * n); // tangent() sets every entry
    tangent(shape, section, points.data(), old, dt, viscous_scale, out.tangent.data());
  }

  std::vector<double> rod_element_tangent_by_ad(const ElementShape &shape, const SectionProperties &section,
                                                const material::MomentCurvatureLaw &law, const double *dofs,
                                                const PointState *old, const double dt,
                                                const double viscous_scale)
  {
    const unsigned int n = 3 * shape.n_nodes;
    using Fad = Sacado::Fad::SLFad<double, 12>; // at most 12 dofs (p = 3): no heap
    std::vector<Fad> u(n), r(n);
    for (unsigned int i = 0; i < n; ++i)
      u[i] = Fad(n, i, dofs[i]);
    residual<Fad>(shape, section, law, u.data(), old, dt, viscous_scale, r.data(), nullptr);
    std::vector<double> K(n * n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        K[i * n + j] = r[i].dx(j);
    return K;
  }

  double rod_element_energy(const ElementShape &shape, const SectionProperties &section,
                            const material::MomentCurvatureLaw &law, const double *dofs,
                            const PointState *old)
  {
    double e = 0.0;
    for (unsigned int q = 0; q < shape.n_q; ++q)
      {
        const auto k = kinematics(shape, q, dofs);
        e += shape.weight[q] * (0.5 * section.EA * k.eps * k.eps + 0.5 * section.GA * k.gamma * k.gamma +
                                law.elastic_energy(k.kappa, old[q].plastic));
      }
    return e;
  }
} // namespace wirefem::fem
