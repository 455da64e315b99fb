// The channel walls of the rod FEM: a lateral penalty on the part of an
// element inside a channel (fem::channel_wall_element).
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>

#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

namespace wirefem::fem
{
  using core::Vec2;

  namespace
  {
    /// At most 4 nodes (degree 3): the element's arrays live on the stack.
    constexpr unsigned int max_nodes = 4;
    using NodeValues = std::array<double, max_nodes>;

    /// along(w, e) = sum_a w_a X_a . e over the nn nodal positions X.
    double along(const unsigned int nn, const double *w, const double *X, const Vec2 &e)
    {
      double v = 0;
      for (unsigned int a = 0; a < nn; ++a)
        v += w[a] * (X[2 * a] * e.x + X[2 * a + 1] * e.y);
      return v;
    }

    /// Gauss-Legendre with nn points on [0, 1], made once per nn.
    const dealii::QGauss<1> &gauss_rule(const unsigned int nn)
    {
      static const std::array<dealii::QGauss<1>, max_nodes> rules = {
          {dealii::QGauss<1>(1), dealii::QGauss<1>(2), dealii::QGauss<1>(3), dealii::QGauss<1>(4)}};
      return rules[nn - 1];
    }

    /// The part of channel_wall_element from the moving end of its
    /// integral, the point xi* where the element leaves the channel:
    /// dU/dxi* = +-(k/2) y*^2 h (+ when the inside part ends at xi*),
    /// dxi*/dX = -(ds/dX)/(ds/dxi) at xi*; its tangent by central
    /// differences of the gradient.
    void add_channel_mouth_terms(const std::vector<double> &pos, const double h, const double k,
                                 const double *X, const Vec2 &ax, const Vec2 &n, const double cut,
                                 const bool inside_first, double *grad, double *tangent)
    {
      const unsigned int nn = pos.size(), nd = 2 * nn;
      NodeValues N, dN;
      lagrange_basis(pos, cut, N.data(), dN.data());
      const double y = along(nn, N.data(), X, n), ds = along(nn, dN.data(), X, ax);
      const double dU = (inside_first ? 1.0 : -1.0) * 0.5 * k * y * y * h;
      for (unsigned int a = 0; a < nn; ++a)
        {
          grad[2 * a] -= dU * N[a] * ax.x / ds;
          grad[2 * a + 1] -= dU * N[a] * ax.y / ds;
        }
      if (!tangent)
        return;
      const double step = 1e-6;
      std::array<double, 2 * max_nodes> Xs, gp, gm;
      std::copy(X, X + nd, Xs.begin());
      double dummy;
      for (unsigned int j = 0; j < nd; ++j)
        {
          Xs[j] = X[j] + step;
          channel_wall_element(pos, h, k, Xs.data(), ax, n, dummy, gp.data());
          Xs[j] = X[j] - step;
          channel_wall_element(pos, h, k, Xs.data(), ax, n, dummy, gm.data());
          Xs[j] = X[j];
          for (unsigned int i = 0; i < nd; ++i)
            tangent[i * nd + j] = (gp[i] - gm[i]) / (2.0 * step);
        }
    }
  } // namespace

  bool channel_wall_element(const std::vector<double> &pos, const double h, const double k, const double *X,
                            const Vec2 &ax, const Vec2 &n, double &U, double *grad, double *tangent)
  {
    const unsigned int nn = pos.size(), nd = 2 * nn;
    if (nn < 2 || nn > max_nodes)
      throw std::invalid_argument("channel_wall_element: 2 to 4 nodes (degree 1 to 3)");
    NodeValues N, dN;
    auto basis = [&](const double xi) { lagrange_basis(pos, xi, N.data(), dN.data()); };
    basis(0.0);
    const double s0 = along(nn, N.data(), X, ax);
    basis(1.0);
    const double s1 = along(nn, N.data(), X, ax);
    U = 0;
    std::fill(grad, grad + nd, 0.0);
    const bool crossing = (s0 < 0.0) != (s1 < 0.0);
    if (s0 >= 0.0 && s1 >= 0.0)
      return false;
    double xa = 0.0, xb = 1.0, cut = 0.0;
    if (crossing && nn == 2)
      {
        // s is linear in xi on a linear element.
        cut = s0 / (s0 - s1);
        (s0 < 0.0 ? xb : xa) = cut;
      }
    else if (crossing)
      {
        double lo = 0.0, hi = 1.0; // s(lo) and s(hi) of opposite signs
        for (int it = 0; it < 60; ++it)
          {
            const double mid = 0.5 * (lo + hi);
            basis(mid);
            ((along(nn, N.data(), X, ax) < 0.0) == (s0 < 0.0) ? lo : hi) = mid;
          }
        cut = 0.5 * (lo + hi);
        (s0 < 0.0 ? xb : xa) = cut;
      }
    // Gauss-Legendre with nn points (exact for y^2, degree 2p), on [xa, xb].
    const auto &gauss = gauss_rule(nn);
    if (tangent)
      std::fill(tangent, tangent + nd * nd, 0.0);
    for (unsigned int q = 0; q < nn; ++q)
      {
        const double xi = xa + (xb - xa) * gauss.point(q)[0];
        const double w = gauss.weight(q) * (xb - xa) * h;
        basis(xi);
        const double y = along(nn, N.data(), X, n);
        U += 0.5 * k * w * y * y;
        for (unsigned int a = 0; a < nn; ++a)
          {
            grad[2 * a] += k * w * y * N[a] * n.x;
            grad[2 * a + 1] += k * w * y * N[a] * n.y;
          }
        if (tangent && !crossing) // quadratic in X: k int N_a N_b n n^T
          for (unsigned int i = 0; i < nd; ++i)
            for (unsigned int j = 0; j < nd; ++j)
              tangent[i * nd + j] += k * w * N[i / 2] * N[j / 2] * (i % 2 ? n.y : n.x) * (j % 2 ? n.y : n.x);
      }
    if (crossing)
      add_channel_mouth_terms(pos, h, k, X, ax, n, cut, s0 < 0.0, grad, tangent);
    return true;
  }
} // namespace wirefem::fem
