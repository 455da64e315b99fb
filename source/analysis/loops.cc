// Loop count (docs/analysis.md) on the planar map of the centreline and its
// self-contacts (CGAL's Arrangement_2 with exact constructions, so wire
// crossings at overlaps split edges robustly).
#include <wirefem/analysis/observables.h>

#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace wirefem::analysis
{
  using core::Vec2;

  namespace
  {
    using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
    using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
    /// Label of an edge: >= 0 the index of a wire piece along the wire,
    /// < 0 a contact chord. Overlapping pieces (degenerate input) keep the
    /// smaller label.
    struct KeepSmaller
    {
      int operator()(const int a, const int b) const { return std::min(a, b); }
    };
    using Traits = CGAL::Arr_curve_data_traits_2<SegmentTraits, int, KeepSmaller>;
    using Arrangement = CGAL::Arrangement_2<Traits>;

    /// The wire refined so that every contact point is one of its vertices:
    /// a chord then starts and ends exactly on the wire.
    struct Refined
    {
      std::vector<Vec2> vertex;
      std::vector<std::pair<int, int>> chord; // vertex indices
    };

    Refined refine(const core::WireState &wire)
    {
      struct Mark
      {
        double s;
        Vec2 x;
        int contact; // -1: a point of the wire
        int end;     // 0: s_a, 1: s_b
      };
      std::vector<Mark> marks;
      marks.reserve(wire.points.size() + 2 * wire.self_contacts.size());
      for (std::size_t k = 0; k < wire.points.size(); ++k)
        marks.push_back({wire.arc_length[k], wire.points[k], -1, 0});
      for (std::size_t c = 0; c < wire.self_contacts.size(); ++c)
        {
          const auto &sc = wire.self_contacts[c];
          marks.push_back({sc.s_a, sc.x_a, static_cast<int>(c), 0});
          marks.push_back({sc.s_b, sc.x_b, static_cast<int>(c), 1});
        }
      // Wire points before contact points at equal arc length.
      std::stable_sort(marks.begin(), marks.end(), [](const Mark &a, const Mark &b) {
        return a.s < b.s || (a.s == b.s && a.contact < b.contact);
      });
      Refined r;
      std::vector<std::pair<int, int>> ends(wire.self_contacts.size(), {-1, -1});
      const double tiny = 1e-9 * wire.diameter;
      for (const auto &m : marks)
        {
          // A mark within `tiny` of the last vertex (a contact at a node) is
          // that vertex: no zero-length pieces.
          if (r.vertex.empty() || norm(m.x - r.vertex.back()) > tiny)
            r.vertex.push_back(m.x);
          if (m.contact >= 0)
            (m.end == 0 ? ends[m.contact].first : ends[m.contact].second) =
                static_cast<int>(r.vertex.size()) - 1;
        }
      std::set<std::pair<int, int>> seen;
      for (const auto &[a, b] : ends)
        if (a >= 0 && b >= 0 && a != b && norm(r.vertex[a] - r.vertex[b]) > tiny &&
            seen.insert({std::min(a, b), std::max(a, b)}).second)
          r.chord.push_back({a, b});
      return r;
    }
  } // namespace

  int count_loops(const core::WireState &wire)
  {
    if (wire.points.size() < 3 || wire.self_contacts.empty())
      return 0;
    const Refined r = refine(wire);
    std::vector<Traits::Curve_2> curves;
    curves.reserve(r.vertex.size() + r.chord.size());
    auto point = [&](const int k) { return Kernel::Point_2(r.vertex[k].x, r.vertex[k].y); };
    for (std::size_t k = 0; k + 1 < r.vertex.size(); ++k)
      curves.emplace_back(SegmentTraits::Curve_2(point(k), point(k + 1)), static_cast<int>(k));
    for (std::size_t c = 0; c < r.chord.size(); ++c)
      curves.emplace_back(SegmentTraits::Curve_2(point(r.chord[c].first), point(r.chord[c].second)),
                          -1 - static_cast<int>(c));
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());

    int loops = 0;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f)
      {
        if (f->is_unbounded() || f->number_of_holes() > 0)
          continue;
        int chords = 0;
        std::set<int> pieces;
        auto he = f->outer_ccb();
        const auto first = he;
        do
          {
            const int label = he->curve().data();
            if (label < 0)
              ++chords;
            else
              pieces.insert(label);
          }
        while (++he != first && chords <= 1);
        // One chord and one contiguous stretch of wire.
        if (chords == 1 && !pieces.empty() &&
            *pieces.rbegin() - *pieces.begin() + 1 == static_cast<int>(pieces.size()))
          ++loops;
      }
    return loops;
  }
} // namespace wirefem::analysis

#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/segment_distance.h>

namespace wirefem::analysis
{
  std::vector<core::SelfContact> find_self_contacts(const core::WireState &wire,
                                                    const double exclusion_length)
  {
    std::vector<core::SelfContact> contacts;
    const int n = static_cast<int>(wire.points.size());
    if (n < 2)
      return contacts;
    const double d = wire.diameter;
    const auto candidates = contact::BroadPhase::brute_force(wire.points, 0, n, d, 1);
    const int last_segment = n - 2;
    auto separated = [&](const int i, const int j) { // segments i < j
      return wire.arc_length[j] - wire.arc_length[i + 1] > exclusion_length;
    };
    for (const auto &pair : candidates)
      {
        const int i = pair.i, j = pair.j;
        if (!separated(i, j))
          continue;
        const auto cp =
            contact::closest_points(wire.points[i], wire.points[i + 1], wire.points[j], wire.points[j + 1]);
        if (cp.distance >= d)
          continue;
        // A closest point at the far end of a segment belongs to the next one.
        if ((cp.s >= 1.0 && i < last_segment && i + 1 < j && separated(i + 1, j)) ||
            (cp.t >= 1.0 && j < last_segment))
          continue;
        core::SelfContact c;
        c.s_a = wire.arc_length[i] + cp.s * (wire.arc_length[i + 1] - wire.arc_length[i]);
        c.s_b = wire.arc_length[j] + cp.t * (wire.arc_length[j + 1] - wire.arc_length[j]);
        c.point_a = cp.s < 0.5 ? i : i + 1;
        c.point_b = cp.t < 0.5 ? j : j + 1;
        c.x_a = cp.p;
        c.x_b = cp.q;
        contacts.push_back(c);
      }
    return contacts;
  }
} // namespace wirefem::analysis
