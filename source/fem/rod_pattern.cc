// K's sparsity pattern: which candidate pairs it must hold, whether it
// still holds every pair that can touch, and its rows.
#include "rod_model_impl.h"

#include <algorithm>
#include <cmath>

namespace wirefem::fem
{
  double RodModel::Impl::chord_gap(const dealii::Vector<double> &x, const contact::SegmentPair &pr,
                                   const double cutoff) const
  {
    const Vec2 a0 = position(x, pr.i), a1 = position(x, pr.i + 1), b0 = position(x, pr.j),
               b1 = position(x, pr.j + 1);
    const double gap = contact::box_gap(a0, a1, b0, b1);
    return gap < cutoff ? contact::closest_points(a0, a1, b0, b1).distance : gap;
  }

  bool RodModel::Impl::closer_than(const dealii::Vector<double> &x, const contact::SegmentPair &pr,
                                   const double cutoff) const
  {
    return chord_gap(x, pr, cutoff) < cutoff;
  }

  void RodModel::Impl::near_pairs(const dealii::Vector<double> &x, const double reach,
                                  std::vector<contact::SegmentPair> &out) const
  {
    out.clear();
    for (const auto &pr : broad.candidates())
      if (closer_than(x, pr, diameter + reach))
        out.push_back(pr);
  }

  bool RodModel::Impl::pattern_covers(const dealii::Vector<double> &x, const double reach)
  {
    const auto at = [&](const int k) { return position(x, k); };
    // The pairs outside the pattern that the last measurement cannot vouch
    // for are measured; when they are many, all are measured afresh.
    const double needed = sp_slack.needed(reach, broad.n_rebuilds(), at);
    if (std::isfinite(needed))
      {
        std::size_t measured = 0;
        for (const auto &[pr, slack] : sp_slack.outside)
          {
            if (slack >= needed)
              break;
            ++measured;
            if (closer_than(x, pr, reach))
              {
                sp_slack.valid = false;
                return false;
              }
          }
        if (4 * measured <= sp_slack.outside.size())
          return true;
      }
    // Both lists are sorted by (i, j).
    sp_slack.outside.clear();
    int lo = static_cast<int>(n_nodes), hi = -1;
    auto in = sp_pairs.begin();
    for (const auto &pr : broad.candidates())
      {
        while (in != sp_pairs.end() && *in < pr)
          ++in;
        if (in != sp_pairs.end() && *in == pr)
          continue;
        const double apart = chord_gap(x, pr, reach);
        if (apart < reach)
          {
            sp_slack.valid = false;
            return false;
          }
        sp_slack.outside.push_back({pr, apart - reach});
        lo = std::min(lo, pr.i);
        hi = std::max(hi, pr.j + 1);
      }
    std::sort(sp_slack.outside.begin(), sp_slack.outside.end(),
              [](const auto &a, const auto &b) { return a.slack < b.slack; });
    sp_slack.valid = true;
    sp_slack.reach = reach;
    sp_slack.broad_rebuilds = broad.n_rebuilds();
    sp_slack.lo = lo;
    sp_slack.at.clear();
    for (int k = lo; k <= hi; ++k)
      sp_slack.at.push_back(at(k));
    return true;
  }

  void RodModel::Impl::pattern_rows(const int first, const int last,
                                    const std::vector<contact::SegmentPair> &pairs,
                                    std::vector<int> &row_start, std::vector<int> &columns)
  {
    const int n = 3 * (last - first);
    // Each free node's neighbours in K, 4 m + c: local node m, coupled in
    // its first c = 2 (contact) or 3 (element) dofs; sorted below.
    auto &adjacent = sp_adjacent;
    adjacent.resize(last - first);
    for (auto &a : adjacent)
      a.clear();
    // The first `components` dofs of each node of nodes[0..count) with each other.
    const auto couple = [&](const int *nodes, const int count, const int components) {
      for (int a = 0; a < count; ++a)
        for (int b = 0; b < count; ++b)
          if (nodes[a] >= first && nodes[a] < last && nodes[b] >= first && nodes[b] < last)
            adjacent[nodes[a] - first].push_back(4 * (nodes[b] - first) + components);
    };
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        {
          int nodes[6];
          for (unsigned int a_ = 0; a_ <= p; ++a_)
            nodes[a_] = static_cast<int>(cell_node[c][a_]);
          couple(nodes, static_cast<int>(p) + 1, 3);
        }
    // Contact acts on positions only (add_contact). A pair presses each
    // segment's first node onto the other segment (assemble_self_contact):
    // node i with j and j + 1, node j with i and i + 1.
    // Contact along the element: the nodes of the cell of each segment's
    // contact points with the other segment's nodes.
    // One channel: the free tip presses the other segment of its pairs too.
    const int tip = channels.pushes(Side::right) ? -1 : static_cast<int>(n_nodes) - 1;
    const auto press = [&](const int a, const int b) {
      int nodes[9], count = 0;
      if (segment_points.empty())
        nodes[count++] = a;
      else
        for (const unsigned int k : cell_node[a / p])
          nodes[count++] = static_cast<int>(k);
      nodes[count++] = b;
      nodes[count++] = b + 1;
      if (a + 1 == tip)
        nodes[count++] = tip;
      couple(nodes, count, 2);
    };
    for (const auto &pr : pairs)
      {
        press(pr.i, pr.j);
        press(pr.j, pr.i);
      }
    // A node's neighbours in order, each once with its most components;
    // rows 3 m and 3 m + 1 take all, row 3 m + 2 the elements' only.
    row_start.assign(n + 1, 0);
    columns.clear();
    for (int k = 0; k < last - first; ++k)
      {
        auto &a = adjacent[k];
        std::sort(a.begin(), a.end());
        std::size_t kept = 0;
        for (std::size_t q = 0; q < a.size(); ++q)
          if (q + 1 == a.size() || a[q + 1] / 4 != a[q] / 4)
            a[kept++] = a[q];
        a.resize(kept);
        for (int c = 0; c < 3; ++c)
          {
            for (const int mc : a)
              if (c < mc % 4)
                for (int cb = 0; cb < mc % 4; ++cb)
                  columns.push_back(3 * (mc / 4) + cb);
            row_start[3 * k + c + 1] = static_cast<int>(columns.size());
          }
      }
  }

  void RodModel::Impl::rebuild_sparsity(const int first, const int last,
                                        std::vector<contact::SegmentPair> pairs)
  {
    const int lo = 3 * first, n = 3 * (last - first);
    std::vector<int> row_start, columns;
    pattern_rows(first, last, pairs, row_start, columns);
    K.reinit(row_start, columns);
    const unsigned int nd = n_local;
    cell_position.assign(static_cast<std::size_t>(n_cells) * nd * nd, -1);
    const auto local = [&](const unsigned int c, const unsigned int i) {
      const int g = static_cast<int>(3 * cell_node[c][i / 3] + i % 3) - lo;
      return g >= 0 && g < n ? g : -1;
    };
    // A node's three columns are consecutive in each row that holds them.
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_active(c, first, last))
        for (unsigned int i = 0; i < nd; ++i)
          for (unsigned int j = 0; j < nd; j += 3)
            if (local(c, i) >= 0 && local(c, j) >= 0)
              {
                const int at = K.find(local(c, i), local(c, j));
                for (unsigned int cb = 0; cb < 3; ++cb)
                  cell_position[(static_cast<std::size_t>(c) * nd + i) * nd + j + cb] = at + cb;
              }
    lu.analyse(n, std::move(row_start), std::move(columns), 3);
    sp_first = first;
    sp_last = last;
    sp_pairs = std::move(pairs);
    sp_slack.valid = false;
  }
} // namespace wirefem::fem
