#include <wirefem/fem/sparse_direct.h>

#include "band_lu.h"

#include <amd.h>
#include <klu.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace wirefem::fem
{
  // KLU factorises columns (CSC). The rows of A are the columns of A^T, so
  // KLU factorises A^T and klu_tsolve solves A x = b with it.
  struct SparseDirect::Impl
  {
    int n = 0;
    std::vector<int> row_start, columns;
    std::vector<double> values; ///< of the last factorisation
    klu_common common{};
    klu_symbolic *symbolic = nullptr;
    klu_numeric *numeric = nullptr;
    int block = 1;      ///< the rows' block size of the last analyse()
    double lu_work = 0; ///< multiply-subtract pairs of an LU of the pattern (estimate)
    // The band preconditioner of solve_band(): the entries of the pattern
    // that couple blocks at most band_width apart, their positions among
    // the pattern's values and in the band's storage, and its factors.
    int band_width = -1;
    std::vector<int> band_entries;
    std::vector<std::size_t> band_slots;
    BandLU band;
    /// The rest of the pattern (the contacts): the rows that have some,
    /// where each row's entries start (one more), their columns and
    /// positions among the values, and (factorise_band) their values.
    std::vector<int> rest_rows, rest_start, rest_columns, rest_entries;
    std::vector<double> rest_values;
    /// min |U_ii| / max |U_ii| of the last full factorisation.
    double rcond_full = 0.0;
    bool last_full = false; ///< whether the current factors are a full factorisation

    Impl()
    {
      klu_defaults(&common);
      // The rod's tangent is one irreducible block (its pattern is
      // symmetric): no block triangular form to look for.
      common.btf = 0;
    }
    ~Impl() { clear(); }
    void clear_numeric()
    {
      if (numeric)
        klu_free_numeric(&numeric, &common);
    }
    void clear_band() { band_width = -1; }
    void clear()
    {
      clear_numeric();
      clear_band();
      if (symbolic)
        klu_free_symbolic(&symbolic, &common);
    }
    /// The band of the pattern: the entries whose blocks are at most
    /// `width` apart, within block (width + 1) - 1 of the diagonal.
    void analyse_band(const int width)
    {
      band_width = width;
      band.reinit(n, block * (width + 1) - 1);
      band_entries.clear();
      band_slots.clear();
      rest_rows.clear();
      rest_start.assign(1, 0);
      rest_columns.clear();
      rest_entries.clear();
      for (int i = 0; i < n; ++i)
        {
          for (int k = row_start[i]; k < row_start[i + 1]; ++k)
            if (std::abs(columns[k] / block - i / block) <= width)
              {
                band_entries.push_back(k);
                band_slots.push_back(band.slot(i, columns[k]));
              }
            else
              {
                rest_columns.push_back(columns[k]);
                rest_entries.push_back(k);
              }
          if (static_cast<int>(rest_entries.size()) > rest_start.back())
            {
              rest_rows.push_back(i);
              rest_start.push_back(static_cast<int>(rest_entries.size()));
            }
        }
      rest_values.resize(rest_entries.size());
    }
    /// y = A x, A the values of the last factorise_band(): the band's
    /// product, and the rest.
    void multiply_by_parts(const double *x, double *y)
    {
      band.multiply(x, y);
      for (std::size_t r = 0; r < rest_rows.size(); ++r)
        {
          double s = 0.0;
          for (int q = rest_start[r]; q < rest_start[r + 1]; ++q)
            s += rest_values[q] * x[rest_columns[q]];
          y[rest_rows[r]] += s;
        }
    }
    /// Factors of the band of A (values a); false when a pivot vanishes.
    /// Keeps the rest's values for multiply_by_parts.
    bool factorise_band(const std::vector<double> &a)
    {
      // The slots outside the pattern stay as analyse_band() left them: zero.
      for (std::size_t k = 0; k < band_entries.size(); ++k)
        band.entry(band_slots[k]) = a[band_entries[k]];
      for (std::size_t q = 0; q < rest_entries.size(); ++q)
        rest_values[q] = a[rest_entries[q]];
      return band.factorise();
    }
    /// Throws unless a matrix of the analysed pattern (values) and a
    /// right-hand side of its size can be solved (caller: for the message).
    void require(const std::vector<double> &values, const std::vector<double> &b, const char *caller) const
    {
      if (!symbolic || values.size() != columns.size() || static_cast<int>(b.size()) != n)
        throw std::logic_error(std::string("SparseDirect::") + caller +
                               " before analyse, or with values of another pattern");
    }
    bool full(SparseDirect::Statistics &stats)
    {
      clear_numeric();
      last_full = true;
      numeric = klu_factor(row_start.data(), columns.data(), values.data(), symbolic, &common);
      if (!numeric || common.status != KLU_OK)
        return false;
      stats.matrix_entries += static_cast<double>(columns.size());
      stats.factor_entries += static_cast<double>(numeric->lnz) + static_cast<double>(numeric->unz);
      klu_rcond(symbolic, numeric, &common);
      rcond_full = common.rcond;
      return std::isfinite(common.rcond) && common.rcond > 0.0;
    }

    // GMRES's Krylov basis, the preconditioned directions and the
    // Hessenberg matrix, kept between calls (no allocation per solve).
    std::vector<double> basis, directions, hessenberg, cosines, sines, rotated;
    int restart = 0; ///< the most GMRES iterations of this solve: columns of the Hessenberg matrix
    double *v(const int j) { return basis.data() + static_cast<std::size_t>(j) * n; }
    double *z(const int j) { return directions.data() + static_cast<std::size_t>(j) * n; }
    double &h(const int i, const int j)
    {
      return hessenberg[static_cast<std::size_t>(j) * (restart + 1) + i];
    }

    void multiply(const std::vector<double> &a, const double *x, double *y) const
    {
      for (int i = 0; i < n; ++i)
        {
          double s = 0.0;
          for (int k = row_start[i]; k < row_start[i + 1]; ++k)
            s += a[k] * x[columns[k]];
          y[i] = s;
        }
    }
    /// In four partial sums: not a chain of n dependent additions.
    double dot(const double *a, const double *b) const
    {
      double s[4] = {0.0, 0.0, 0.0, 0.0};
      int i = 0;
      for (; i + 3 < n; i += 4)
        for (int l = 0; l < 4; ++l)
          s[l] += a[i + l] * b[i + l];
      for (; i < n; ++i)
        s[0] += a[i] * b[i];
      return (s[0] + s[1]) + (s[2] + s[3]);
    }

    /// w -= c v, then the dot product of w with `next` (w itself: its
    /// square norm), summed as dot() sums: one pass instead of two.
    double subtract_and_dot(double *w, const double c, const double *v, const double *next) const
    {
      double s[4] = {0.0, 0.0, 0.0, 0.0};
      int i = 0;
      for (; i + 3 < n; i += 4)
        for (int l = 0; l < 4; ++l)
          {
            w[i + l] -= c * v[i + l];
            s[l] += w[i + l] * next[i + l];
          }
      for (; i < n; ++i)
        {
          w[i] -= c * v[i];
          s[0] += w[i] * next[i];
        }
      return (s[0] + s[1]) + (s[2] + s[3]);
    }

    /// GMRES on A (values a) from x = 0, right preconditioned by
    /// `precondition` (z -> M^{-1} z in place; false when it fails), with
    /// modified Gram-Schmidt and Givens rotations; true when
    /// |b - A x|_2 <= tolerance, checked on the true residual at the end.
    template <typename Multiply, typename Precondition>
    bool gmres(const Multiply &multiply, const std::vector<double> &b, std::vector<double> &x,
               const double tolerance, const int m, unsigned long &iterations,
               const Precondition &precondition)
    {
      x.assign(n, 0.0);
      const double beta = std::sqrt(dot(b.data(), b.data()));
      if (!std::isfinite(beta))
        return false;
      if (beta <= tolerance)
        return true;
      restart = m;
      basis.resize(static_cast<std::size_t>(m + 1) * n);
      directions.resize(static_cast<std::size_t>(m) * n);
      hessenberg.assign(static_cast<std::size_t>(m + 1) * m, 0.0);
      cosines.assign(m, 0.0);
      sines.assign(m, 0.0);
      rotated.assign(m + 1, 0.0);
      for (int i = 0; i < n; ++i)
        v(0)[i] = b[i] / beta;
      rotated[0] = beta;
      int k = 0;
      bool converged = false;
      for (int j = 0; j < m && !converged; ++j)
        {
          std::copy(v(j), v(j) + n, z(j));
          if (!precondition(z(j)))
            return false;
          double *w = v(j + 1);
          multiply(z(j), w);
          h(0, j) = dot(w, v(0));
          for (int i = 0; i <= j; ++i)
            {
              // w -= h_ij v_i, and the next dot product in the same pass
              // (with v_{i+1}, or with w itself for its norm).
              h(i + 1, j) = subtract_and_dot(w, h(i, j), v(i), i < j ? v(i + 1) : w);
            }
          const double wn = std::sqrt(h(j + 1, j));
          h(j + 1, j) = wn;
          for (int i = 0; i < j; ++i)
            {
              const double t = cosines[i] * h(i, j) + sines[i] * h(i + 1, j);
              h(i + 1, j) = -sines[i] * h(i, j) + cosines[i] * h(i + 1, j);
              h(i, j) = t;
            }
          const double r = std::hypot(h(j, j), h(j + 1, j));
          if (!std::isfinite(r) || r == 0.0)
            return false;
          cosines[j] = h(j, j) / r;
          sines[j] = h(j + 1, j) / r;
          h(j, j) = r;
          h(j + 1, j) = 0.0;
          rotated[j + 1] = -sines[j] * rotated[j];
          rotated[j] *= cosines[j];
          ++iterations;
          k = j + 1;
          converged = std::abs(rotated[j + 1]) <= tolerance || wn == 0.0;
          if (!converged)
            for (int l = 0; l < n; ++l)
              w[l] /= wn;
        }
      return converged && solution(multiply, b, x, tolerance, k);
    }

    /// x = sum y_j z_j with y = H^{-1} g from GMRES's first k iterations;
    /// true when the true residual |b - A x|_2 is within the tolerance.
    template <typename Multiply>
    bool solution(const Multiply &multiply, const std::vector<double> &b, std::vector<double> &x,
                  const double tolerance, const int k)
    {
      std::vector<double> &y = cosines; // no longer needed
      for (int i = k - 1; i >= 0; --i)
        {
          double s = rotated[i];
          for (int j = i + 1; j < k; ++j)
            s -= h(i, j) * y[j];
          y[i] = s / h(i, i);
        }
      for (int j = 0; j < k; ++j)
        for (int l = 0; l < n; ++l)
          x[l] += y[j] * z(j)[l];
      // The true residual, in the first basis vector's storage.
      double *res = v(0);
      multiply(x.data(), res);
      double rr = 0.0;
      for (int i = 0; i < n; ++i)
        {
          res[i] = b[i] - res[i];
          rr += res[i] * res[i];
        }
      return std::isfinite(rr) && std::sqrt(rr) <= tolerance;
    }
  };

  SparseDirect::SparseDirect()
    : impl(std::make_unique<Impl>())
  {
  }
  SparseDirect::~SparseDirect() = default;

  void SparseDirect::analyse(const int n, std::vector<int> row_start, std::vector<int> columns,
                             const int block)
  {
    auto &m = *impl;
    m.clear();
    m.n = n;
    m.block = block;
    m.row_start = std::move(row_start);
    m.columns = std::move(columns);
    if (block > 1)
      {
        // The pattern of the blocks (a block couples to another when any
        // of their entries do), ordered by AMD and expanded: block k's
        // entries take its place in order. A ninth of the graph, about the
        // same fill.
        if (n % block != 0)
          throw std::logic_error("SparseDirect::analyse: the size is not a multiple of the block");
        const int nb = n / block;
        std::vector<int> block_start(nb + 1, 0), block_columns, order(nb);
        block_columns.reserve(m.columns.size() / (block * block) + nb);
        for (int bi = 0; bi < nb; ++bi)
          {
            const auto row_begin = block_columns.size();
            for (int i = block * bi; i < block * (bi + 1); ++i)
              for (int k = m.row_start[i]; k < m.row_start[i + 1]; ++k)
                block_columns.push_back(m.columns[k] / block);
            std::sort(block_columns.begin() + static_cast<std::ptrdiff_t>(row_begin), block_columns.end());
            block_columns.erase(std::unique(block_columns.begin() + static_cast<std::ptrdiff_t>(row_begin),
                                            block_columns.end()),
                                block_columns.end());
            block_start[bi + 1] = static_cast<int>(block_columns.size());
          }
        double info[AMD_INFO];
        if (amd_order(nb, block_start.data(), block_columns.data(), order.data(), nullptr, info) != AMD_OK)
          throw std::runtime_error("AMD could not order the tangent's block pattern");
        // Each pair of the blocks' LU is a product of block x block blocks.
        m.lu_work = info[AMD_NMULTSUBS_LU] * block * block * block;
        std::vector<int> permutation(n);
        for (int k = 0; k < nb; ++k)
          for (int c = 0; c < block; ++c)
            permutation[block * k + c] = block * order[k] + c;
        m.symbolic = klu_analyze_given(n, m.row_start.data(), m.columns.data(), permutation.data(),
                                       permutation.data(), &m.common);
      }
    else
      m.symbolic = klu_analyze(n, m.row_start.data(), m.columns.data(), &m.common);
    if (!m.symbolic)
      throw std::runtime_error("KLU could not analyse the tangent's sparsity pattern");
    if (block <= 1)
      m.lu_work = m.symbolic->est_flops / 2.0;
    ++stats.analyses;
  }

  bool SparseDirect::same_pattern(const std::vector<int> &row_start, const std::vector<int> &columns) const
  {
    return impl->symbolic && row_start == impl->row_start && columns == impl->columns;
  }

  const std::vector<int> &SparseDirect::row_start() const
  {
    return impl->row_start;
  }

  const std::vector<int> &SparseDirect::columns() const
  {
    return impl->columns;
  }

  double SparseDirect::lu_work() const
  {
    return impl->lu_work;
  }

  bool SparseDirect::factorise(const std::vector<double> &values)
  {
    auto &m = *impl;
    if (!m.symbolic || values.size() != m.columns.size())
      throw std::logic_error("SparseDirect::factorise before analyse, or with values of another pattern");
    m.values = values;
    if (m.numeric)
      {
        // The pivot order of the last full factorisation, if the pivots stay
        // as well conditioned as then (within a factor 1e3).
        if (klu_refactor(m.row_start.data(), m.columns.data(), m.values.data(), m.symbolic, m.numeric,
                         &m.common) &&
            klu_rcond(m.symbolic, m.numeric, &m.common) && std::isfinite(m.common.rcond) &&
            m.common.rcond > 1e-3 * m.rcond_full)
          {
            ++stats.refactorisations;
            m.last_full = false;
            return true;
          }
      }
    ++stats.factorisations;
    return m.full(stats);
  }

  bool SparseDirect::solve_kept(const std::vector<double> &values, const std::vector<double> &b,
                                std::vector<double> &x, const double tolerance, const int max_iterations)
  {
    auto &m = *impl;
    m.require(values, b, "solve_kept");
    ++stats.kept_solves;
    if (m.numeric && max_iterations > 0 &&
        m.gmres([&](const double *z, double *y) { m.multiply(values, z, y); }, b, x, tolerance,
                max_iterations, stats.kept_iterations,
                [&m](double *z) { return klu_tsolve(m.symbolic, m.numeric, m.n, 1, z, &m.common) != 0; }))
      return true;
    ++stats.kept_refactorised;
    return factorise(values) && solve(b, x);
  }

  bool SparseDirect::solve_band(const std::vector<double> &values, const std::vector<double> &b,
                                std::vector<double> &x, const double tolerance, const int max_iterations,
                                const int width)
  {
    auto &m = *impl;
    m.require(values, b, "solve_band");
    ++stats.band_solves;
    if (m.band_width != width)
      m.analyse_band(width);
    if (m.factorise_band(values) && m.gmres([&m](const double *z, double *y) { m.multiply_by_parts(z, y); },
                                            b, x, tolerance, max_iterations, stats.band_iterations,
                                            [&m](double *z) {
                                              m.band.solve(z);
                                              return true;
                                            }))
      return true;
    ++stats.band_refactorised;
    return factorise(values) && solve(b, x);
  }

  bool SparseDirect::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    auto &m = *impl;
    if (!m.numeric)
      throw std::logic_error("SparseDirect::solve before factorise");
    ++stats.solves;
    x = b;
    if (!klu_tsolve(m.symbolic, m.numeric, m.n, 1, x.data(), &m.common))
      return false;
    double bmax = 0.0, rmax = 0.0;
    bool finite = true;
    for (int i = 0; i < m.n; ++i)
      {
        double r = b[i];
        for (int k = m.row_start[i]; k < m.row_start[i + 1]; ++k)
          r -= m.values[k] * x[m.columns[k]];
        finite = finite && std::isfinite(x[i]) && std::isfinite(r);
        bmax = std::max(bmax, std::abs(b[i]));
        rmax = std::max(rmax, std::abs(r));
      }
    if (finite && rmax <= 1e-10 * bmax)
      return true;
    if (m.last_full)
      return finite;
    ++stats.inaccurate;
    ++stats.factorisations;
    if (!m.full(stats))
      return false;
    x = b;
    return klu_tsolve(m.symbolic, m.numeric, m.n, 1, x.data(), &m.common) &&
           std::all_of(x.begin(), x.end(), [](const double v) { return std::isfinite(v); });
  }
} // namespace wirefem::fem
