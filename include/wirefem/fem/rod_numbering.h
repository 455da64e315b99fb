// Node and dof numbering of a single rod of n_cells Lagrange elements of
// degree p (the static set-ups of fem/: cantilever, capstan): element c owns
// the vertices c p and (c + 1) p and the interior nodes in between, local
// order vertices first (rod_element.h); node k carries the dofs 3 k + (x, y,
// theta).
#pragma once

#include <vector>

namespace dealii
{
  class SparsityPattern;
  template <typename number>
  class SparseMatrix;
} // namespace dealii

namespace wirefem::fem
{
  struct RodNumbering
  {
    unsigned int p = 1;
    unsigned int n_cells = 1;

    unsigned int n_nodes() const { return n_cells * p + 1; }
    unsigned int n_dofs() const { return 3 * n_nodes(); }
    /// Global node of local node a of element c.
    unsigned int node(unsigned int c, unsigned int a) const
    {
      return a == 0 ? c * p : a == 1 ? (c + 1) * p : c * p + a - 1;
    }
    /// The 3 (p + 1) global dofs of element c, in local order.
    void cell_dofs(unsigned int c, std::vector<unsigned int> &dofs) const
    {
      dofs.resize(3 * (p + 1));
      for (unsigned int a = 0; a <= p; ++a)
        for (unsigned int comp = 0; comp < 3; ++comp)
          dofs[3 * a + comp] = 3 * node(c, a) + comp;
    }
    /// The sparsity of the assembled tangent: every element's dofs coupled.
    void make_sparsity(dealii::SparsityPattern &sparsity) const;
  };

  /// Eliminates a prescribed dof i from an assembled tangent with a
  /// symmetric sparsity: row i becomes the identity row, column i is zeroed
  /// elsewhere (so the correction of dof i is the residual's entry, zero
  /// once that is cleared).
  void fix_dof(dealii::SparseMatrix<double> &K, unsigned int i);
} // namespace wirefem::fem
