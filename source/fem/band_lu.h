// The band preconditioner of SparseDirect::solve_band(): a band matrix,
// its product and its LU without pivoting (not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace wirefem::fem
{
  /// A band matrix (the entries within `half` of the diagonal, stored
  /// densely by rows, 2 half + 1 each), its product with a vector and its
  /// LU without pivoting. The rod's tangent, nodes in order along the
  /// wire, is such a band but for its contacts; its diagonal blocks carry
  /// the mass and the stiffness and keep their pivots away from zero. A
  /// vanishing or non-finite pivot is reported, and the caller then
  /// solves otherwise. The LU costs n half^2 multiply-adds, a solve or a
  /// product about 2 n half. The widths of elements of degree 1 to 3
  /// (half = 5, 8, 11) have loops of fixed length.
  class BandLU
  {
  public:
    void reinit(const int rows, const int half_width)
    {
      n = rows;
      half = half_width;
      width = 2 * half + 1;
      band.assign(static_cast<std::size_t>(n) * width, 0.0);
      row_max.assign(n, 0.0);
      inverse_pivot.assign(n, 0.0);
      padded.assign(static_cast<std::size_t>(n) + 2 * half, 0.0);
    }
    /// Where entry (i, j), |i - j| <= half, is stored.
    std::size_t slot(const int i, const int j) const
    {
      return static_cast<std::size_t>(i) * width + static_cast<std::size_t>(j - i + half);
    }
    double &entry(const std::size_t s) { return band[s]; }

    /// The LU of the entries set: L (unit diagonal, below) and U. False
    /// when a pivot is not finite or below 1e-14 of its row's largest entry.
    bool factorise()
    {
      return dispatch([this](auto h) { return factorise_fixed<decltype(h)::value>(); });
    }
    /// x <- (LU)^{-1} x.
    void solve(double *x)
    {
      dispatch([this, x](auto h) {
        solve_fixed<decltype(h)::value>(x);
        return true;
      });
    }
    /// y = B x, B the entries set.
    void multiply(const double *x, double *y)
    {
      dispatch([this, x, y](auto h) {
        multiply_fixed<decltype(h)::value>(x, y);
        return true;
      });
    }

  private:
    int n = 0, half = 0, width = 1;
    std::vector<double> band, lu, row_max, inverse_pivot, padded;

    template <typename F>
    bool dispatch(const F &f)
    {
      switch (half)
        {
        case 5:
          return f(std::integral_constant<int, 5>{});
        case 8:
          return f(std::integral_constant<int, 8>{});
        case 11:
          return f(std::integral_constant<int, 11>{});
        default:
          return f(std::integral_constant<int, 0>{});
        }
    }
    /// x in padded storage: y[-half, n + half), zero outside [0, n).
    double *pad(const double *x)
    {
      double *y = padded.data() + half;
      std::copy(x, x + n, y);
      return y;
    }

    template <int H>
    bool factorise_fixed()
    {
      const int h = H > 0 ? H : half, w = 2 * h + 1;
      lu = band;
      for (int i = 0; i < n; ++i)
        {
          double m = 0.0;
          const double *r = &lu[slot(i, i - h)];
          for (int s = 0; s < w; ++s)
            m = std::max(m, std::abs(r[s]));
          row_max[i] = m;
        }
      for (int k = 0; k < n; ++k)
        {
          double *uk = &lu[slot(k, k)];
          const double pivot = uk[0];
          if (!std::isfinite(pivot) || !(std::abs(pivot) > 1e-14 * row_max[k]))
            return false;
          const double inverse = 1.0 / pivot;
          inverse_pivot[k] = inverse;
          // Row k + q's entry (k + q, k) is w - 1 after (k, k); the
          // columns past the last row are zeros of row k.
          const int rows = std::min(h, n - 1 - k);
          for (int q = 1; q <= rows; ++q)
            {
              double *ui = uk + q * (w - 1);
              if (ui[0] == 0.0)
                continue;
              const double l = ui[0] * inverse;
              ui[0] = l;
              for (int j = 1; j <= h; ++j)
                ui[j] -= l * uk[j];
            }
        }
      return true;
    }

    template <int H>
    void solve_fixed(double *x)
    {
      // Two partial sums, and the term of the row just solved last: the
      // sweeps' chain of dependent operations is one multiply-add a row.
      const int h = H > 0 ? H : half;
      double *y = pad(x);
      for (int i = 0; i < n; ++i)
        {
          const double *r = &lu[slot(i, i - h)];
          double s0 = 0.0, s1 = 0.0;
          for (int m = 0; m + 1 < h; m += 2)
            {
              s0 += r[m] * y[i - h + m];
              s1 += r[m + 1] * y[i - h + m + 1];
            }
          double s = y[i] - (s0 + s1);
          if (h % 2 == 1)
            s -= r[h - 1] * y[i - 1];
          y[i] = s;
        }
      for (int i = n - 1; i >= 0; --i)
        {
          const double *r = &lu[slot(i, i)];
          double s0 = 0.0, s1 = 0.0;
          for (int m = h; m > 1; m -= 2)
            {
              s0 += r[m] * y[i + m];
              s1 += r[m - 1] * y[i + m - 1];
            }
          double s = y[i] - (s0 + s1);
          if (h % 2 == 1)
            s -= r[1] * y[i + 1];
          y[i] = s * inverse_pivot[i];
        }
      std::copy(y, y + n, x);
    }

    template <int H>
    void multiply_fixed(const double *x, double *out)
    {
      const int h = H > 0 ? H : half, w = 2 * h + 1;
      const double *y = pad(x);
      for (int i = 0; i < n; ++i)
        {
          const double *r = &band[slot(i, i - h)];
          const double *yi = y + i - h;
          double s0 = r[0] * yi[0], s1 = 0.0;
          for (int m = 1; m + 1 < w; m += 2)
            {
              s0 += r[m] * yi[m];
              s1 += r[m + 1] * yi[m + 1];
            }
          out[i] = s0 + s1;
        }
    }
  };
} // namespace wirefem::fem
