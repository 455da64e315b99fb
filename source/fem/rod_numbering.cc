#include <wirefem/fem/rod_numbering.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
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
} // namespace wirefem::fem
