// The KLU wrapper of the rod FEM: solutions against a known answer, the
// refactorisation path and its fall-back to a full factorisation, a
// singular matrix refused, and GMRES on kept factors (solve_kept): to its
// tolerance on a nearby matrix, with a factorisation when it is far; GMRES
// on the band's LU (solve_band): to its tolerance, in as many iterations on
// a rod five times as long, with a direct solve when it does not get there;
// the band's own LU (no pivoting) exact on a band of each element degree,
// and a zero pivot of it handed to a direct solve. The
// tangent's storage (CsrMatrix): blocks added where a dense matrix has them.
#include <wirefem/fem/csr_matrix.h>
#include <wirefem/fem/sparse_direct.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace
{
  using wirefem::fem::SparseDirect;

  // A rod-like pattern: 3 x 3 blocks of each node with its neighbours, and
  // a few couplings between distant nodes (contacts); rows sorted.
  struct Pattern
  {
    int n = 0;
    std::vector<int> row_start, columns;
  };

  Pattern rod_pattern(const int nodes, std::mt19937 &gen)
  {
    std::vector<std::set<int>> rows(3 * nodes);
    auto couple = [&](int a, int b) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            rows[3 * a + i].insert(3 * b + j);
            rows[3 * b + j].insert(3 * a + i);
          }
    };
    for (int k = 0; k < nodes; ++k)
      {
        couple(k, k);
        if (k + 1 < nodes)
          couple(k, k + 1);
      }
    std::uniform_int_distribution<int> node(0, nodes - 1);
    for (int c = 0; c < nodes / 5; ++c)
      couple(node(gen), node(gen));
    Pattern p;
    p.n = 3 * nodes;
    p.row_start.push_back(0);
    for (const auto &r : rows)
      {
        p.columns.insert(p.columns.end(), r.begin(), r.end());
        p.row_start.push_back(static_cast<int>(p.columns.size()));
      }
    return p;
  }

  // Unsymmetric values, diagonally dominant.
  std::vector<double> values(const Pattern &p, std::mt19937 &gen)
  {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> v(p.columns.size());
    for (int i = 0; i < p.n; ++i)
      for (int k = p.row_start[i]; k < p.row_start[i + 1]; ++k)
        v[k] = p.columns[k] == i ? 20.0 + u(gen) : u(gen);
    return v;
  }

  std::vector<double> multiply(const Pattern &p, const std::vector<double> &v, const std::vector<double> &x)
  {
    std::vector<double> b(p.n, 0.0);
    for (int i = 0; i < p.n; ++i)
      for (int k = p.row_start[i]; k < p.row_start[i + 1]; ++k)
        b[i] += v[k] * x[p.columns[k]];
    return b;
  }

  double max_error(const std::vector<double> &a, const std::vector<double> &b)
  {
    double e = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      e = std::max(e, std::abs(a[i] - b[i]));
    return e;
  }

  TEST(SparseDirect, SolvesARodLikeSystemAndRefactorisesWithTheSamePattern)
  {
    std::mt19937 gen(3);
    const auto p = rod_pattern(200, gen);
    SparseDirect lu;
    lu.analyse(p.n, p.row_start, p.columns);
    EXPECT_TRUE(lu.same_pattern(p.row_start, p.columns));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x_true(p.n), x;
    for (auto &xi : x_true)
      xi = u(gen);
    for (int round = 0; round < 3; ++round)
      {
        const auto v = values(p, gen);
        ASSERT_TRUE(lu.factorise(v));
        ASSERT_TRUE(lu.solve(multiply(p, v, x_true), x));
        EXPECT_LT(max_error(x, x_true), 1e-12) << "round " << round;
      }
    EXPECT_EQ(lu.statistics().analyses, 1u);
    EXPECT_EQ(lu.statistics().factorisations, 1u);
    EXPECT_EQ(lu.statistics().refactorisations, 2u);
    EXPECT_EQ(lu.statistics().solves, 3u);
    // The fill is counted at full factorisations only: L and U hold at
    // least A's entries and the diagonal twice; a rod's pattern, ordered
    // by AMD, fills little.
    const auto &st = lu.statistics();
    EXPECT_EQ(st.matrix_entries, static_cast<double>(p.columns.size()));
    EXPECT_GE(st.factor_entries, st.matrix_entries + p.n);
    EXPECT_LT(st.factor_entries, 3.0 * st.matrix_entries);
  }

  TEST(SparseDirect, AnOrderingOfNodeBlocksSolvesAsWellAndFillsAboutAsLittle)
  {
    // The rod FEM orders the graph of its nodes (3 dofs each): same
    // solution, and the fill within a factor of the ordering of the dofs.
    std::mt19937 gen(5);
    const auto p = rod_pattern(300, gen);
    const auto v = values(p, gen);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x_true(p.n), x;
    for (auto &xi : x_true)
      xi = u(gen);
    double fill[2];
    for (const int block : {1, 3})
      {
        SparseDirect lu;
        lu.analyse(p.n, p.row_start, p.columns, block);
        ASSERT_TRUE(lu.factorise(v));
        ASSERT_TRUE(lu.solve(multiply(p, v, x_true), x));
        EXPECT_LT(max_error(x, x_true), 1e-12) << "block " << block;
        fill[block == 3] = lu.statistics().factor_entries / lu.statistics().matrix_entries;
      }
    EXPECT_LT(fill[1], 1.3 * fill[0]);
    EXPECT_THROW(SparseDirect().analyse(p.n, p.row_start, p.columns, 7), std::logic_error)
        << "a size that is not a multiple of the block";
  }

  TEST(SparseDirect, FallsBackToPivotingWhenTheKeptPivotsFail)
  {
    // A full 2 x 2 pattern: first with a dominant diagonal, then with a zero
    // one, where the first pivot order divides by zero.
    const std::vector<int> row_start{0, 2, 4}, columns{0, 1, 0, 1};
    SparseDirect lu;
    lu.analyse(2, row_start, columns);
    std::vector<double> x;
    ASSERT_TRUE(lu.factorise({4.0, 1.0, 1.0, 3.0}));
    ASSERT_TRUE(lu.solve({5.0, 4.0}, x));
    EXPECT_NEAR(x[0], 1.0, 1e-14);
    EXPECT_NEAR(x[1], 1.0, 1e-14);
    ASSERT_TRUE(lu.factorise({0.0, 2.0, 3.0, 1e-9}));
    ASSERT_TRUE(lu.solve({2.0, 3.0}, x));
    EXPECT_NEAR(x[0], 1.0 - 1e-9 / 3.0, 1e-12);
    EXPECT_NEAR(x[1], 1.0, 1e-12);
    EXPECT_GE(lu.statistics().factorisations, 2u) << "the kept pivot order was used on a zero pivot";
  }

  double norm2(const std::vector<double> &a)
  {
    double s = 0.0;
    for (const double v : a)
      s += v * v;
    return std::sqrt(s);
  }

  TEST(SparseDirect, KeptFactorsSolveANearbyMatrixToTheTolerance)
  {
    std::mt19937 gen(5);
    const auto p = rod_pattern(300, gen);
    SparseDirect lu;
    lu.analyse(p.n, p.row_start, p.columns);
    const auto v0 = values(p, gen);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x_true(p.n), x;
    for (auto &xi : x_true)
      xi = u(gen);
    // Without factors the first call factorises.
    ASSERT_TRUE(lu.solve_kept(v0, multiply(p, v0, x_true), x, 1e-10, 8));
    EXPECT_EQ(lu.statistics().kept_refactorised, 1u);
    EXPECT_LT(max_error(x, x_true), 1e-11);
    // A matrix 1% away: GMRES on v0's factors, the true residual below
    // each tolerance asked for, in more iterations for a tighter one and
    // without a factorisation.
    auto v1 = v0;
    for (auto &vi : v1)
      vi *= 1.0 + 0.01 * u(gen);
    const auto b = multiply(p, v1, x_true);
    unsigned long iterations = lu.statistics().kept_iterations;
    std::vector<unsigned long> used;
    for (const double relative : {1e-4, 1e-8, 1e-12})
      {
        const double tol = relative * norm2(b);
        ASSERT_TRUE(lu.solve_kept(v1, b, x, tol, 20)) << relative;
        auto r = multiply(p, v1, x);
        for (int i = 0; i < p.n; ++i)
          r[i] = b[i] - r[i];
        EXPECT_LE(norm2(r), tol) << relative;
        EXPECT_GT(norm2(r), 1e-6 * tol) << "far below the tolerance: was it solved directly?";
        used.push_back(lu.statistics().kept_iterations - iterations);
        iterations = lu.statistics().kept_iterations;
      }
    EXPECT_EQ(lu.statistics().kept_refactorised, 1u);
    EXPECT_EQ(lu.statistics().factorisations + lu.statistics().refactorisations, 1u);
    EXPECT_LT(used[0], used[1]);
    EXPECT_LT(used[1], used[2]);
    // Too few iterations allowed for that tolerance: v1 is factorised and
    // solved directly, and its factors are kept for the next call.
    ASSERT_TRUE(lu.solve_kept(v1, b, x, 1e-12 * norm2(b), 1));
    EXPECT_EQ(lu.statistics().kept_refactorised, 2u);
    EXPECT_LT(max_error(x, x_true), 1e-11);
    ASSERT_TRUE(lu.solve_kept(v1, b, x, 1e-12 * norm2(b), 1));
    EXPECT_EQ(lu.statistics().kept_refactorised, 2u) << "the new factors were not kept";
  }

  TEST(SparseDirect, TheBandsFactorsSolveToTheToleranceInIterationsThatDoNotGrowWithTheSize)
  {
    // Rod-like matrices of 300 and 1500 nodes: the band (each node with its
    // neighbours) is factorised, the couplings of distant nodes (a fifth
    // as many as nodes, as contacts) are left to GMRES.
    std::vector<unsigned long> used;
    for (const int nodes : {300, 1500})
      {
        std::mt19937 gen(7);
        const auto p = rod_pattern(nodes, gen);
        SparseDirect lu;
        lu.analyse(p.n, p.row_start, p.columns, 3);
        auto v = values(p, gen);
        // Distant couplings as strong as the band's off-diagonal entries:
        // the band alone is not the matrix.
        for (int i = 0; i < p.n; ++i)
          for (int k = p.row_start[i]; k < p.row_start[i + 1]; ++k)
            if (std::abs(p.columns[k] / 3 - i / 3) > 1)
              v[k] *= 4.0;
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::vector<double> x_true(p.n), x;
        for (auto &xi : x_true)
          xi = u(gen);
        const auto b = multiply(p, v, x_true);
        for (const double relative : {1e-3, 1e-9})
          {
            const unsigned long before = lu.statistics().band_iterations;
            const double tol = relative * norm2(b);
            ASSERT_TRUE(lu.solve_band(v, b, x, tol, 60, 1)) << relative;
            auto r = multiply(p, v, x);
            for (int i = 0; i < p.n; ++i)
              r[i] = b[i] - r[i];
            EXPECT_LE(norm2(r), tol) << relative;
            EXPECT_GT(norm2(r), 1e-6 * tol) << "far below the tolerance: was it solved directly?";
            const unsigned long n_it = lu.statistics().band_iterations - before;
            EXPECT_GT(n_it, 1u) << "the band alone solved it: the test has no distant couplings";
            used.push_back(n_it);
          }
        EXPECT_EQ(lu.statistics().band_refactorised, 0u);
        EXPECT_EQ(lu.statistics().factorisations + lu.statistics().refactorisations, 0u);
        // Too few iterations for the tolerance: solved directly.
        ASSERT_TRUE(lu.solve_band(v, b, x, 1e-12 * norm2(b), 1, 1));
        EXPECT_EQ(lu.statistics().band_refactorised, 1u);
        EXPECT_LT(max_error(x, x_true), 1e-11);
      }
    // Iterations for each tolerance: at most one more on the longer rod.
    EXPECT_LE(used[2], used[0] + 1);
    EXPECT_LE(used[3], used[1] + 1);
    EXPECT_LT(used[0], used[1]);
  }

  std::vector<double> random_vector(const int n, std::mt19937 &gen)
  {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> x(n);
    for (auto &xi : x)
      xi = u(gen);
    return x;
  }

  /// Node blocks of 3 coupled to the blocks at most `width` apart, and
  /// nothing else: a matrix that is its own band.
  Pattern band_pattern(const int nodes, const int width)
  {
    Pattern p;
    p.n = 3 * nodes;
    p.row_start.push_back(0);
    for (int i = 0; i < p.n; ++i)
      {
        for (int j = std::max(0, 3 * (i / 3 - width)); j < std::min(p.n, 3 * (i / 3 + width + 1)); ++j)
          p.columns.push_back(j);
        p.row_start.push_back(static_cast<int>(p.columns.size()));
      }
    return p;
  }

  TEST(SparseDirect, TheBandsOwnLUSolvesABandOfEachElementDegreeInOneIteration)
  {
    // Degrees 1-3 (widths 1-3 blocks) have loops of fixed length, 4 the
    // general one: each solves its own band exactly, so GMRES stops after
    // its first iteration with the residual at rounding level.
    for (const int width : {1, 2, 3, 4})
      {
        std::mt19937 gen(17 + width);
        const auto p = band_pattern(250, width);
        const auto v = values(p, gen);
        const auto x_true = random_vector(p.n, gen);
        const auto b = multiply(p, v, x_true);
        std::vector<double> x;
        SparseDirect lu;
        lu.analyse(p.n, p.row_start, p.columns, 3);
        ASSERT_TRUE(lu.solve_band(v, b, x, 1e-12 * norm2(b), 5, width)) << width;
        EXPECT_EQ(lu.statistics().band_iterations, 1u) << width;
        EXPECT_EQ(lu.statistics().band_refactorised, 0u) << width;
        EXPECT_LT(max_error(x, x_true), 1e-12) << width;
      }
  }

  TEST(SparseDirect, AZeroPivotOfTheBandIsSolvedDirectly)
  {
    // The first node's block swaps its first two dofs ([[0 1] [1 0]]):
    // the matrix is regular, but an LU without pivoting meets a zero
    // first pivot. The band's LU reports it and the matrix is solved by a
    // factorisation with pivoting.
    std::mt19937 gen(5);
    const auto p = band_pattern(50, 1);
    auto v = values(p, gen);
    for (int i = 0; i < 2; ++i)
      for (int k = p.row_start[i]; k < p.row_start[i + 1]; ++k)
        v[k] = p.columns[k] == 1 - i ? 20.0 : 0.0;
    const auto x_true = random_vector(p.n, gen);
    const auto b = multiply(p, v, x_true);
    std::vector<double> x;
    SparseDirect lu;
    lu.analyse(p.n, p.row_start, p.columns, 3);
    ASSERT_TRUE(lu.solve_band(v, b, x, 1e-9 * norm2(b), 5, 1));
    EXPECT_EQ(lu.statistics().band_iterations, 0u);
    EXPECT_EQ(lu.statistics().band_refactorised, 1u);
    EXPECT_LT(max_error(x, x_true), 1e-12);
  }

  TEST(SparseDirect, TheLUWorkEstimateGrowsWithTheCouplingsOfDistantNodes)
  {
    // A chain of node blocks has an LU without fill: the same work per
    // entry at any length. Couplings between distant nodes (contacts)
    // cost more per entry, and more on the longer rod.
    const auto work_per_entry = [](const int nodes, const bool contacts) {
      std::mt19937 gen(11);
      // Without contacts, only the band: entries within one block of the diagonal's.
      const auto p = contacts ? rod_pattern(nodes, gen) : band_pattern(nodes, 1);
      SparseDirect lu;
      lu.analyse(p.n, p.row_start, p.columns, 3);
      return lu.lu_work() / static_cast<double>(p.columns.size());
    };
    const double chain = work_per_entry(300, false);
    EXPECT_GT(chain, 0.0);
    EXPECT_NEAR(work_per_entry(1500, false), chain, 0.01 * chain);
    const double contacts = work_per_entry(300, true);
    EXPECT_GT(contacts, 2.0 * chain);
    EXPECT_GT(work_per_entry(1500, true), 1.5 * contacts);
  }

  TEST(SparseDirect, RefusesASingularMatrix)
  {
    const std::vector<int> row_start{0, 2, 4}, columns{0, 1, 0, 1};
    SparseDirect lu;
    lu.analyse(2, row_start, columns);
    EXPECT_FALSE(lu.factorise({1.0, 2.0, 2.0, 4.0}));
  }

  TEST(CsrMatrix, AddsBlocksWhereADenseMatrixHasThem)
  {
    // Blocks of random nodes (3 dofs each, or the first 2 as a contact's)
    // added into a rod pattern holding them, against a dense matrix; dofs
    // outside the range kept are skipped.
    std::mt19937 gen(11);
    const int nodes = 20;
    std::vector<std::set<int>> rows(3 * nodes);
    struct Block
    {
      std::vector<int> nodes;
      int components;
    };
    std::vector<Block> blocks;
    std::uniform_int_distribution<int> node(0, nodes - 1);
    for (int b = 0; b < 40; ++b)
      {
        Block blk{{node(gen), node(gen), node(gen)}, b % 2 ? 3 : 2};
        blk.nodes.resize(b % 3 == 0 ? 1 : 3);
        if (blk.nodes.size() == 3 &&
            (blk.nodes[0] == blk.nodes[1] || blk.nodes[1] == blk.nodes[2] || blk.nodes[0] == blk.nodes[2]))
          continue;
        for (const int ka : blk.nodes)
          for (const int kb : blk.nodes)
            for (int ca = 0; ca < blk.components; ++ca)
              for (int cb = 0; cb < blk.components; ++cb)
                rows[3 * ka + ca].insert(3 * kb + cb);
        blocks.push_back(blk);
      }
    std::vector<int> row_start{0}, columns;
    for (const auto &r : rows)
      {
        columns.insert(columns.end(), r.begin(), r.end());
        row_start.push_back(static_cast<int>(columns.size()));
      }
    wirefem::fem::CsrMatrix K;
    K.reinit(row_start, columns);
    const int n = 3 * nodes, skip = 5; // the first `skip` dofs are not kept
    std::vector<double> dense(n * n, 0.0);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (const auto &blk : blocks)
      {
        std::vector<int> dofs, component;
        for (const int k : blk.nodes)
          for (int c = 0; c < blk.components; ++c)
            {
              dofs.push_back(3 * k + c < skip ? -1 : 3 * k + c);
              component.push_back(c);
            }
        const int m = static_cast<int>(dofs.size());
        std::vector<double> block(m * m);
        for (auto &v : block)
          v = value(gen);
        K.add_block(dofs.data(), component.data(), m, block.data(), 0.5);
        for (int a = 0; a < m; ++a)
          for (int b = 0; b < m; ++b)
            if (dofs[a] >= 0 && dofs[b] >= 0)
              dense[dofs[a] * n + dofs[b]] += 0.5 * block[a * m + b];
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        {
          EXPECT_EQ(K.el(i, j), dense[i * n + j]) << i << ", " << j;
          EXPECT_EQ(K.find(i, j) >= 0, rows[i].count(j) == 1) << i << ", " << j;
        }
    // add_at through positions found once, and the product with a vector.
    const int at[2] = {K.find(7, 7), -1};
    const double add[2] = {2.0, 100.0};
    const double before = K.el(7, 7);
    K.add_at(at, 2, add, 0.25);
    EXPECT_EQ(K.el(7, 7), before + 0.5);
    dense[7 * n + 7] += 0.5;
    std::vector<double> x(n), y(n);
    for (auto &v : x)
      v = value(gen);
    K.vmult(x.data(), y.data());
    for (int i = 0; i < n; ++i)
      {
        double s = 0.0;
        for (int j = 0; j < n; ++j)
          s += dense[i * n + j] * x[j];
        EXPECT_NEAR(y[i], s, 1e-14) << i;
      }
    K.zero();
    EXPECT_EQ(*std::max_element(K.values().begin(), K.values().end()), 0.0);
  }
} // namespace
