// The rod's tangent as sorted rows (CSR), the layout the sparse LU reads,
// so that assembly writes straight into the values the factorisation
// takes. The pattern holds whole blocks of a node's dofs: the columns of
// one node in a row are consecutive, and add_block() finds a node's first
// column by bisection and the others by stepping along.
#pragma once

#include <algorithm>
#include <cassert>
#include <vector>

namespace wirefem::fem
{
  class CsrMatrix
  {
  public:
    /// A new pattern of n rows: the start of each row (n + 1 entries) and
    /// the column of each entry, sorted within rows. The values are zero.
    void reinit(std::vector<int> row_start, std::vector<int> columns)
    {
      starts = std::move(row_start);
      cols = std::move(columns);
      vals.assign(cols.size(), 0.0);
    }
    int m() const { return starts.empty() ? 0 : static_cast<int>(starts.size()) - 1; }
    const std::vector<int> &row_start() const { return starts; }
    const std::vector<int> &columns() const { return cols; }
    const std::vector<double> &values() const { return vals; }
    void zero() { std::fill(vals.begin(), vals.end(), 0.0); }

    /// The position of entry (i, j) among the values, or -1 when it is not
    /// in the pattern.
    int find(const int i, const int j) const
    {
      const auto b = cols.begin() + starts[i], e = cols.begin() + starts[i + 1];
      const auto it = std::lower_bound(b, e, j);
      return it != e && *it == j ? static_cast<int>(it - cols.begin()) : -1;
    }
    /// Entry (i, j); zero when it is not in the pattern.
    double el(const int i, const int j) const
    {
      const int k = find(i, j);
      return k < 0 ? 0.0 : vals[k];
    }
    /// Sets entry (i, j), which must be in the pattern.
    void set(const int i, const int j, const double v)
    {
      const int k = find(i, j);
      assert(k >= 0);
      vals[k] = v;
    }

    /// Adds scale * block to the rows and columns `dofs[0..n)` (local dof
    /// numbers; -1 skips one), block row major with n columns. Each dof
    /// is component c of a node whose first dof, dofs[i] - c, is in the
    /// pattern together with all its components the block reaches:
    /// component c sits c entries after the first.
    void add_block(const int *dofs, const int *component, const int n, const double *block,
                   const double scale)
    {
      // A node's first column in row i is first sought where it sat in
      // the row before, shifted by the rows' starts (rows of one node hold
      // the same columns), and bisected for when it is not there.
      constexpr int most = 18;
      assert(n <= most);
      int start_of[most] = {};
      int previous_row = -1;
      for (int a = 0; a < n; ++a)
        {
          const int i = dofs[a];
          if (i < 0)
            continue;
          const int shift = previous_row < 0 ? 0 : starts[i] - starts[previous_row];
          int node_start = -1, node_first = -1;
          for (int b = 0; b < n; ++b)
            {
              const int j = dofs[b];
              if (j < 0)
                continue;
              const int first = j - component[b];
              if (first != node_first)
                {
                  node_first = first;
                  const int guess = start_of[b] + shift;
                  node_start = previous_row >= 0 && guess < starts[i + 1] && cols[guess] == first
                                   ? guess
                                   : find(i, first);
                  assert(node_start >= 0);
                }
              start_of[b] = node_start;
              assert(cols[node_start + component[b]] == j);
              vals[node_start + component[b]] += scale * block[a * n + b];
            }
          previous_row = i;
        }
    }

    /// Adds scale * block[k] to the value at position[k] (from find())
    /// for the n entries with a position >= 0.
    void add_at(const int *position, const int n, const double *block, const double scale)
    {
      for (int k = 0; k < n; ++k)
        if (position[k] >= 0)
          vals[position[k]] += scale * block[k];
    }

    /// y = A x.
    void vmult(const double *x, double *y) const
    {
      for (int i = 0; i < m(); ++i)
        {
          double s = 0.0;
          for (int k = starts[i]; k < starts[i + 1]; ++k)
            s += vals[k] * x[cols[k]];
          y[i] = s;
        }
    }

  private:
    std::vector<int> starts, cols;
    std::vector<double> vals;
  };
} // namespace wirefem::fem
