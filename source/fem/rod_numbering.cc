#include <wirefem/fem/rod_numbering.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

namespace wirefem::fem
{
  void RodNumbering::make_sparsity(dealii::SparsityPattern &sparsity) const
  {
    dealii::DynamicSparsityPattern dsp(n_dofs(), n_dofs());
    std::vector<unsigned int> local;
    for (unsigned int c = 0; c < n_cells; ++c)
      {
        cell_dofs(c, local);
        for (const auto i : local)
          for (const auto j : local)
            dsp.add(i, j);
      }
    sparsity.copy_from(dsp);
  }

  void fix_dof(dealii::SparseMatrix<double> &K, const unsigned int i)
  {
    for (auto it = K.begin(i); it != K.end(i); ++it)
      {
        const unsigned int j = it->column();
        it->value() = j == i ? 1.0 : 0.0;
        if (j != i)
          K.set(j, i, 0.0);
      }
  }
} // namespace wirefem::fem
