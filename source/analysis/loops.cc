// Loop count (docs/analysis.md) on the planar map of the centreline and its
// self-contacts: traced face by face on the planar graph, with proper
// crossings split at their (rounded) crossing points; where segments touch
// or overlap (exact predicates), through CGAL's Arrangement_2 with exact
// constructions instead.
#include <wirefem/analysis/observables.h>

#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
    // The planar graph's tests need exact predicates only.
    using EpickPoint = CGAL::Exact_predicates_inexact_constructions_kernel::Point_2;
    using EpickSegment = CGAL::Exact_predicates_inexact_constructions_kernel::Segment_2;

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

    /// The refined wire's pieces (label k >= 0 along the wire) and its
    /// chords (label -1 - c) as a graph on the refined vertices.
    struct PlanarGraph
    {
      struct Edge
      {
        int a, b, label;
      };
      std::vector<EpickPoint> p;
      std::vector<Vec2> x;
      std::vector<Edge> edges;
      int origin(const int h) const { return (h & 1) ? edges[h >> 1].b : edges[h >> 1].a; }
      int target(const int h) const { return (h & 1) ? edges[h >> 1].a : edges[h >> 1].b; }
    };

    PlanarGraph planar_graph(const Refined &r)
    {
      PlanarGraph g;
      const int nv = static_cast<int>(r.vertex.size());
      g.x = r.vertex;
      g.p.reserve(nv);
      for (const auto &v : r.vertex)
        g.p.emplace_back(v.x, v.y);
      g.edges.reserve(nv - 1 + r.chord.size());
      for (int k = 0; k + 1 < nv; ++k)
        g.edges.push_back({k, k + 1, k});
      for (std::size_t c = 0; c < r.chord.size(); ++c)
        g.edges.push_back({r.chord[c].first, r.chord[c].second, -1 - static_cast<int>(c)});
      return g;
    }

    /// Vertices at one point made one (as the arrangement does: a wire
    /// crossing itself, with its contact marks at the crossing); edges
    /// that shrink to a point are dropped.
    void merge_coincident_vertices(PlanarGraph &g)
    {
      const auto &p = g.p;
      std::vector<int> order(p.size()), same(p.size());
      for (std::size_t k = 0; k < p.size(); ++k)
        order[k] = static_cast<int>(k);
      std::sort(order.begin(), order.end(), [&](const int a, const int b) { return p[a] < p[b]; });
      for (std::size_t k = 0; k < order.size(); ++k)
        same[order[k]] = k > 0 && p[order[k]] == p[order[k - 1]] ? same[order[k - 1]] : order[k];
      std::vector<PlanarGraph::Edge> kept;
      kept.reserve(g.edges.size());
      for (const auto &e : g.edges)
        if (same[e.a] != same[e.b])
          kept.push_back({same[e.a], same[e.b], e.label});
      g.edges = std::move(kept);
    }

    /// Calls found(i, j) once for every pair i < j of boxes that overlap
    /// (closed boxes), through a uniform grid of cells twice the mean box
    /// size, sorted by cell: O(N log N) for the short, local edges of a
    /// wire. A pair is reported by the cell holding the lower-left corner
    /// of its overlap. Boxes spread over too many cells (a few very long
    /// edges) go to CGAL's box intersection instead.
    template <typename Found>
    void for_each_overlapping_pair(const std::vector<CGAL::Bbox_2> &boxes, Found &&found)
    {
      if (boxes.size() < 2)
        return;
      CGAL::Bbox_2 all = boxes.front();
      double size = 0.0;
      for (const auto &b : boxes)
        {
          all += b;
          size += std::max(b.xmax() - b.xmin(), b.ymax() - b.ymin());
        }
      const double extent = std::max({all.xmax() - all.xmin(), all.ymax() - all.ymin(), 1.0});
      const double h = std::max(2.0 * size / boxes.size(), 1e-6 * extent); // at most 1e6 cells a side
      auto cell = [&](const double v, const double lo) { return static_cast<std::int64_t>((v - lo) / h); };
      const std::int64_t ny = cell(all.ymax(), all.ymin()) + 1;
      std::vector<std::pair<std::int64_t, int>> entries;
      entries.reserve(4 * boxes.size());
      const std::size_t budget = 16 * boxes.size();
      bool over_budget = false;
      for (std::size_t k = 0; k < boxes.size() && !over_budget; ++k)
        {
          const auto x0 = cell(boxes[k].xmin(), all.xmin()), x1 = cell(boxes[k].xmax(), all.xmin());
          const auto y0 = cell(boxes[k].ymin(), all.ymin()), y1 = cell(boxes[k].ymax(), all.ymin());
          over_budget =
              static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1) + entries.size() > budget;
          for (auto ix = x0; ix <= x1 && !over_budget; ++ix)
            for (auto iy = y0; iy <= y1; ++iy)
              entries.push_back({ix * ny + iy, static_cast<int>(k)});
        }
      if (over_budget)
        {
          using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, int>;
          std::vector<Box> tree;
          for (std::size_t k = 0; k < boxes.size(); ++k)
            tree.emplace_back(boxes[k], static_cast<int>(k));
          CGAL::box_self_intersection_d(tree.begin(), tree.end(), [&](const Box &x, const Box &y) {
            found(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
          });
          return;
        }
      std::sort(entries.begin(), entries.end());
      for (std::size_t first = 0, last = 0; first < entries.size(); first = last)
        {
          while (last < entries.size() && entries[last].first == entries[first].first)
            ++last;
          for (std::size_t i = first; i < last; ++i)
            for (std::size_t j = i + 1; j < last; ++j)
              {
                const auto &a = boxes[entries[i].second], &b = boxes[entries[j].second];
                if (a.xmax() < b.xmin() || b.xmax() < a.xmin() || a.ymax() < b.ymin() || b.ymax() < a.ymin())
                  continue;
                const double x = std::max(a.xmin(), b.xmin()), y = std::max(a.ymin(), b.ymin());
                if (cell(x, all.xmin()) * ny + cell(y, all.ymin()) == entries[first].first)
                  found(entries[i].second, entries[j].second);
              }
        }
    }

    /// The pairs of edges that cross properly (each one's ends strictly on
    /// both sides of the other); false when two edges meet in any other way
    /// than at a common end, or two edges from a common end overlap (exact
    /// predicates on the given doubles). Candidates: edges whose bounding
    /// boxes overlap.
    bool find_crossings(const PlanarGraph &g, std::vector<std::pair<int, int>> &crossings)
    {
      const auto &p = g.p;
      std::vector<CGAL::Bbox_2> boxes;
      boxes.reserve(g.edges.size());
      for (const auto &e : g.edges)
        boxes.push_back(p[e.a].bbox() + p[e.b].bbox());
      bool degenerate = false;
      for_each_overlapping_pair(boxes, [&](const int ie, const int jf) {
        const auto &e = g.edges[ie], &f = g.edges[jf];
        int shared = -1, pe = -1, pf = -1, common = 0;
        for (const int u : {e.a, e.b})
          for (const int v : {f.a, f.b})
            if (u == v)
              {
                ++common;
                shared = u;
                pe = u == e.a ? e.b : e.a;
                pf = v == f.a ? f.b : f.a;
              }
        if (common > 1)
          degenerate = true; // two edges between the same vertices
        else if (common == 1)
          degenerate = degenerate || (CGAL::orientation(p[shared], p[pe], p[pf]) == CGAL::COLLINEAR &&
                                      CGAL::angle(p[pe], p[shared], p[pf]) == CGAL::ACUTE);
        else if (CGAL::do_intersect(EpickSegment(p[e.a], p[e.b]), EpickSegment(p[f.a], p[f.b])))
          {
            const auto o1 = CGAL::orientation(p[e.a], p[e.b], p[f.a]),
                       o2 = CGAL::orientation(p[e.a], p[e.b], p[f.b]);
            const auto o3 = CGAL::orientation(p[f.a], p[f.b], p[e.a]),
                       o4 = CGAL::orientation(p[f.a], p[f.b], p[e.b]);
            if (o1 * o2 < 0 && o3 * o4 < 0)
              crossings.push_back({ie, jf});
            else
              degenerate = true; // an end on the other edge, or collinear
          }
      });
      return !degenerate;
    }

    /// The graph with each proper crossing made a vertex (in floating
    /// point) that splits both edges; the pieces keep their edge's label.
    PlanarGraph split_at_crossings(const PlanarGraph &g, const std::vector<std::pair<int, int>> &crossings)
    {
      PlanarGraph s;
      s.x = g.x;
      std::vector<std::vector<std::pair<double, int>>> cuts(g.edges.size()); // (parameter, vertex)
      for (const auto &[e, f] : crossings)
        {
          const Vec2 a = g.x[g.edges[e].a], b = g.x[g.edges[e].b];
          const Vec2 c = g.x[g.edges[f].a], d = g.x[g.edges[f].b];
          auto cross = [](const Vec2 u, const Vec2 v) { return u.x * v.y - u.y * v.x; };
          const double t = cross(c - a, d - c) / cross(b - a, d - c);
          const double u = cross(c - a, b - a) / cross(b - a, d - c);
          const int v = static_cast<int>(s.x.size());
          s.x.push_back(a + t * (b - a));
          cuts[e].push_back({t, v});
          cuts[f].push_back({u, v});
        }
      for (const auto &x : s.x)
        s.p.emplace_back(x.x, x.y);
      for (std::size_t e = 0; e < g.edges.size(); ++e)
        {
          auto &c = cuts[e];
          std::sort(c.begin(), c.end());
          int from = g.edges[e].a;
          for (const auto &[t, v] : c)
            {
              s.edges.push_back({from, v, g.edges[e].label});
              from = v;
            }
          s.edges.push_back({from, g.edges[e].b, g.edges[e].label});
        }
      return s;
    }

    /// Half-edges 2e (a -> b) and 2e + 1 (b -> a); around[start[v] ..
    /// start[v + 1]) are those leaving v in counter-clockwise order (exact:
    /// half-plane, then orientation), slot[h] is h's place there.
    struct Rotation
    {
      std::vector<int> start, around, slot;
    };

    Rotation rotation_system(const PlanarGraph &g)
    {
      const int nv = static_cast<int>(g.p.size()), nh = 2 * static_cast<int>(g.edges.size());
      Rotation rot{std::vector<int>(nv + 1, 0), std::vector<int>(nh), std::vector<int>(nh)};
      for (int h = 0; h < nh; ++h)
        ++rot.start[g.origin(h) + 1];
      for (int v = 0; v < nv; ++v)
        rot.start[v + 1] += rot.start[v];
      std::vector<int> fill(rot.start.begin(), rot.start.end() - 1);
      for (int h = 0; h < nh; ++h)
        rot.around[fill[g.origin(h)]++] = h;
      for (int v = 0; v < nv; ++v)
        {
          const EpickPoint &o = g.p[v];
          auto upper = [&](const int h) {
            const EpickPoint &t = g.p[g.target(h)];
            return t.y() > o.y() || (t.y() == o.y() && t.x() > o.x());
          };
          std::sort(rot.around.begin() + rot.start[v], rot.around.begin() + rot.start[v + 1],
                    [&](const int a, const int b) {
                      const bool ua = upper(a), ub = upper(b);
                      if (ua != ub)
                        return ua;
                      return CGAL::orientation(o, g.p[g.target(a)], g.p[g.target(b)]) == CGAL::LEFT_TURN;
                    });
          for (int k = rot.start[v]; k < rot.start[v + 1]; ++k)
            rot.slot[rot.around[k]] = k;
        }
      return rot;
    }

    /// Traces every face (to the left of its half-edges) and counts those
    /// bounded by one chord and one contiguous stretch of wire. The graph
    /// is connected (the wire joins all its vertices), so no face has holes
    /// and the one traced clockwise (the most negative area) is unbounded.
    int trace_loop_faces(const PlanarGraph &g, const Rotation &rot)
    {
      const int nh = 2 * static_cast<int>(g.edges.size());
      // The face continues with the edge clockwise next to h's twin.
      auto next = [&](const int h) {
        const int twin = h ^ 1, v = g.origin(twin), k = rot.slot[twin];
        return rot.around[k == rot.start[v] ? rot.start[v + 1] - 1 : k - 1];
      };
      std::vector<char> seen(nh, 0);
      std::vector<std::pair<double, bool>> faces; // area, loop
      std::vector<int> pieces;
      for (int h0 = 0; h0 < nh; ++h0)
        {
          if (seen[h0])
            continue;
          double area = 0.0;
          int chords = 0;
          pieces.clear();
          const Vec2 o = g.x[g.origin(h0)]; // areas about a vertex of the face: no cancellation
          for (int h = h0; !seen[h]; h = next(h))
            {
              seen[h] = 1;
              const Vec2 a = g.x[g.origin(h)] - o, b = g.x[g.target(h)] - o;
              area += a.x * b.y - a.y * b.x;
              const int label = g.edges[h >> 1].label;
              if (label < 0)
                ++chords;
              else
                pieces.push_back(label);
            }
          std::sort(pieces.begin(), pieces.end());
          pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
          faces.push_back({area, chords == 1 && !pieces.empty() &&
                                     pieces.back() - pieces.front() + 1 == static_cast<int>(pieces.size())});
        }
      const auto outer = std::min_element(faces.begin(), faces.end());
      int loops = 0;
      for (auto f = faces.begin(); f != faces.end(); ++f)
        loops += f != outer && f->second;
      return loops;
    }
  } // namespace

  namespace
  {
    int planar_loops(const Refined &r)
    {
      if (r.chord.empty())
        return 0;
      PlanarGraph g = planar_graph(r);
      merge_coincident_vertices(g);
      std::vector<std::pair<int, int>> crossings;
      if (!find_crossings(g, crossings))
        return -1;
      if (!crossings.empty())
        {
          // Chords that cross (contacts fanning out from one piece), or wire
          // crossing at a large overlap: split there, and check again that
          // the rounded crossing points made nothing degenerate.
          g = split_at_crossings(g, crossings);
          crossings.clear();
          merge_coincident_vertices(g);
          if (!find_crossings(g, crossings) || !crossings.empty())
            return -1;
        }
      return trace_loop_faces(g, rotation_system(g));
    }

    int arrangement_loops(const Refined &r)
    {
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
  } // namespace

  // The wire is refined once; the arrangement is the fall-back of the tracing.
  int count_loops(const core::WireState &wire)
  {
    if (wire.points.size() < 3 || wire.self_contacts.empty())
      return 0;
    const Refined r = refine(wire);
    const int planar = planar_loops(r);
    return planar >= 0 ? planar : arrangement_loops(r);
  }

  int count_loops_planar(const core::WireState &wire)
  {
    return wire.points.size() < 3 || wire.self_contacts.empty() ? 0 : planar_loops(refine(wire));
  }

  int count_loops_arrangement(const core::WireState &wire)
  {
    return wire.points.size() < 3 || wire.self_contacts.empty() ? 0 : arrangement_loops(refine(wire));
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
    // The simulation's broad phase (box intersection, O(N log N)); its
    // candidates closer than d + skin are a superset of the contacts below.
    contact::BroadPhase broad(d, 1e-6 * d, 1);
    broad.update(wire.points, 0, n);
    const auto &candidates = broad.candidates();
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
