// The channel walls of the rod FEM: a lateral penalty on the part of an
// element inside a channel (fem::channel_wall_element).
#include <wirefem/fem/contact_element.h>
#include <wirefem/fem/rod_element.h>

#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <vector>

namespace wirefem::fem
{
  using core::Vec2;

  namespace
  {
    /// along(w, e) = sum_a w_a X_a . e for the element's nodal positions X.
    double along(const std::vector<double> &w, const double *X, const Vec2 &e)
    {
      double v = 0;
      for (unsigned int a = 0; a < w.size(); ++a)
        v += w[a] * (X[2 * a] * e.x + X[2 * a + 1] * e.y);
      return v;
    }

    /// The part of channel_wall_element from the moving end of its
    /// integral, the point xi* where the element leaves the channel:
    /// dU/dxi* = +-(k/2) y*^2 h (+ when the inside part ends at xi*),
    /// dxi*/dX = -(ds/dX)/(ds/dxi) at xi*; its tangent by central
    /// differences of the gradient.
    void add_channel_mouth_terms(const std::vector<double> &pos, const double h, const double k,
                                 const double *X, const Vec2 &ax, const double cut, const bool inside_first,
                                 double *grad, double *tangent)
    {
      const unsigned int nn = pos.size(), nd = 2 * nn;
      std::vector<double> N(nn), dN(nn);
      lagrange_basis(pos, cut, N.data(), dN.data());
      const double y = along(N, X, perp(ax)), ds = along(dN, X, ax);
      const double dU = (inside_first ? 1.0 : -1.0) * 0.5 * k * y * y * h;
      for (unsigned int a = 0; a < nn; ++a)
        {
          grad[2 * a] -= dU * N[a] * ax.x / ds;
          grad[2 * a + 1] -= dU * N[a] * ax.y / ds;
        }
      if (!tangent)
        return;
      const double step = 1e-6;
      std::vector<double> Xs(X, X + nd), gp(nd), gm(nd);
      double dummy;
      for (unsigned int j = 0; j < nd; ++j)
        {
          Xs[j] = X[j] + step;
          channel_wall_element(pos, h, k, Xs.data(), ax, dummy, gp.data());
          Xs[j] = X[j] - step;
          channel_wall_element(pos, h, k, Xs.data(), ax, dummy, gm.data());
          Xs[j] = X[j];
          for (unsigned int i = 0; i < nd; ++i)
            tangent[i * nd + j] = (gp[i] - gm[i]) / (2.0 * step);
        }
    }
  } // namespace

  bool channel_wall_element(const std::vector<double> &pos, const double h, const double k, const double *X,
                            const Vec2 &ax, double &U, double *grad, double *tangent)
  {
    const unsigned int nn = pos.size(), nd = 2 * nn;
    const Vec2 n = perp(ax);
    std::vector<double> N(nn), dN(nn);
    auto basis = [&](const double xi) { lagrange_basis(pos, xi, N.data(), dN.data()); };
    auto along = [&](const double *w, const Vec2 &e) {
      double v = 0;
      for (unsigned int a = 0; a < nn; ++a)
        v += w[a] * (X[2 * a] * e.x + X[2 * a + 1] * e.y);
      return v;
    };
    basis(0.0);
    const double s0 = along(N.data(), ax);
    basis(1.0);
    const double s1 = along(N.data(), ax);
    U = 0;
    std::fill(grad, grad + nd, 0.0);
    const bool crossing = (s0 < 0.0) != (s1 < 0.0);
    if (s0 >= 0.0 && s1 >= 0.0)
      return false;
    double xa = 0.0, xb = 1.0, cut = 0.0;
    if (crossing)
      {
        double lo = 0.0, hi = 1.0; // s(lo) and s(hi) of opposite signs
        for (int it = 0; it < 60; ++it)
          {
            const double mid = 0.5 * (lo + hi);
            basis(mid);
            ((along(N.data(), ax) < 0.0) == (s0 < 0.0) ? lo : hi) = mid;
          }
        cut = 0.5 * (lo + hi);
        (s0 < 0.0 ? xb : xa) = cut;
      }
    // Gauss-Legendre with nn points (exact for y^2, degree 2p), on [xa, xb].
    const dealii::QGauss<1> gauss(nn);
    if (tangent)
      std::fill(tangent, tangent + nd * nd, 0.0);
    for (unsigned int q = 0; q < nn; ++q)
      {
        const double xi = xa + (xb - xa) * gauss.point(q)[0];
        const double w = gauss.weight(q) * (xb - xa) * h;
        basis(xi);
        const double y = along(N.data(), n);
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
      add_channel_mouth_terms(pos, h, k, X, ax, cut, s0 < 0.0, grad, tangent);
    return true;
  }
} // namespace wirefem::fem
