#include <wirefem/fem/sparse_direct.h>

#include <klu.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
    void clear()
    {
      clear_numeric();
      if (symbolic)
        klu_free_symbolic(&symbolic, &common);
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
  };

  SparseDirect::SparseDirect()
    : impl(std::make_unique<Impl>())
  {
  }
  SparseDirect::~SparseDirect() = default;

  void SparseDirect::analyse(const int n, std::vector<int> row_start, std::vector<int> columns)
  {
    auto &m = *impl;
    m.clear();
    m.n = n;
    m.row_start = std::move(row_start);
    m.columns = std::move(columns);
    m.symbolic = klu_analyze(n, m.row_start.data(), m.columns.data(), &m.common);
    if (!m.symbolic)
      throw std::runtime_error("KLU could not analyse the tangent's sparsity pattern");
    ++stats.analyses;
  }

  bool SparseDirect::same_pattern(const std::vector<int> &row_start, const std::vector<int> &columns) const
  {
    return impl->symbolic && row_start == impl->row_start && columns == impl->columns;
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
