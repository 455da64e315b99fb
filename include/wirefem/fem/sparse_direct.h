// Sparse LU of the rod's tangent with KLU (SuiteSparse): the fill-reducing
// ordering and symbolic analysis once per sparsity pattern, and later
// factorisations of the same pattern with the pivot order of the last full
// one (KLU's refactorisation), falling back to a full factorisation when
// the result is not accurate. The matrix is given by rows (CSR), the
// values in the pattern's order. SuiteSparse stays in the .cc file.
//
// solve_kept() solves a matrix of the same pattern without factorising it:
// GMRES on it, preconditioned (on the right, so that the residual it
// minimises is the true one) by the kept factors of an earlier matrix; a
// matrix that has drifted too far from those factors for GMRES to converge
// in a few iterations is factorised and solved directly, and its factors
// are kept in turn. Newton's tangents change little from one iteration to
// the next, and a solve with factors costs a small fraction of a
// factorisation.
#pragma once

#include <memory>
#include <vector>

namespace wirefem::fem
{
  class SparseDirect
  {
  public:
    SparseDirect();
    ~SparseDirect();
    SparseDirect(const SparseDirect &) = delete;
    SparseDirect &operator=(const SparseDirect &) = delete;

    /// A new pattern: n rows, row_start (n + 1 entries) and the column of
    /// each entry. Orders and analyses it; drops any factorisation. With
    /// block > 1 the rows come in blocks of that size (the dofs of a node)
    /// and the ordering keeps each block together: it orders the graph of
    /// the blocks, which is block^2 times smaller.
    void analyse(int n, std::vector<int> row_start, std::vector<int> columns, int block = 1);

    /// Whether the pattern is that of the last analyse().
    bool same_pattern(const std::vector<int> &row_start, const std::vector<int> &columns) const;
    /// The pattern of the last analyse(): the start of each row (n + 1
    /// entries) and the column of each entry, sorted within rows.
    const std::vector<int> &row_start() const;
    const std::vector<int> &columns() const;
    /// The multiply-subtract pairs an LU of the last analyse()'s pattern
    /// takes, as its ordering estimates them (with blocks: AMD's count on
    /// the blocks' graph times block^3).
    double lu_work() const;

    /// Factorises the matrix with these values (one per entry of the
    /// pattern). Returns false when it is singular.
    bool factorise(const std::vector<double> &values);

    /// Solves A x = b for the last factorisation. When the residual
    /// |b - A x| exceeds 1e-10 |b| (max norms) after a refactorisation, the
    /// matrix is factorised afresh with pivoting and solved again. Returns
    /// false when the matrix is singular or the solution is not finite.
    bool solve(const std::vector<double> &b, std::vector<double> &x);

    /// Solves A x = b, A given by these values, to |b - A x|_2 <= tolerance
    /// by GMRES (at most max_iterations) preconditioned by the kept factors;
    /// without factors, or when GMRES does not get there, factorises A and
    /// solves as solve() does. Returns false when A is singular or x is not
    /// finite.
    bool solve_kept(const std::vector<double> &values, const std::vector<double> &b, std::vector<double> &x,
                    double tolerance, int max_iterations);

    /// Solves A x = b, A given by these values, to |b - A x|_2 <= tolerance
    /// by GMRES (at most max_iterations) preconditioned by the LU of A's
    /// band: the entries that couple blocks (analyse()'s) at most `width`
    /// apart, which for the rod are its elements and leave out the contacts
    /// between distant stretches of wire. The band's LU (dense band
    /// storage, no pivoting: source/fem/band_lu.h) costs in proportion to
    /// the size, and so do GMRES's iterations, whose number does not grow
    /// with the size. When the band meets a vanishing pivot or GMRES does
    /// not get there, factorises A and solves as solve() does.
    bool solve_band(const std::vector<double> &values, const std::vector<double> &b, std::vector<double> &x,
                    double tolerance, int max_iterations, int width);

    struct Statistics
    {
      unsigned long analyses = 0;
      unsigned long factorisations = 0;   ///< full, with pivoting
      unsigned long refactorisations = 0; ///< with the pivot order kept
      unsigned long solves = 0;
      unsigned long inaccurate = 0;        ///< refactorisations redone for accuracy
      unsigned long kept_solves = 0;       ///< solve_kept() calls
      unsigned long kept_iterations = 0;   ///< GMRES iterations of solve_kept()
      unsigned long kept_refactorised = 0; ///< solve_kept() calls that factorised
      unsigned long band_solves = 0;       ///< solve_band() calls
      unsigned long band_iterations = 0;   ///< GMRES iterations of solve_band()
      unsigned long band_refactorised = 0; ///< solve_band() calls that factorised A
      /// Entries of the matrix and of its factors L + U, summed over the
      /// full factorisations (their ratio is the mean fill).
      double matrix_entries = 0.0, factor_entries = 0.0;
    };
    const Statistics &statistics() const { return stats; }

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
    Statistics stats;
  };
} // namespace wirefem::fem
