// Candidate wire-wire contact pairs (the broad phase), Verlet-list style.
//
// Segment k joins nodes k and k+1 of a node array indexed by stable storage
// indices; the active nodes are [first_node, last_node). A pair of segments is
// a candidate when their centrelines were closer than diameter + skin at the
// last rebuild and they are more than `exclusion` segments apart along the
// wire (|i - j| > exclusion). The list is rebuilt only when a node moved more
// than skin/2 since the last rebuild or the active range changed, so between
// rebuilds it holds every pair that can be closer than `diameter`.
// CGAL's box_intersection_d finds the candidates; it stays inside the .cc file.
#pragma once

#include <wirefem/core/vec2.h>

#include <vector>

namespace wirefem::contact
{
  /// Two segments (storage indices of their first nodes), i < j.
  struct SegmentPair
  {
    int i = 0;
    int j = 0;
    friend bool operator==(const SegmentPair &a, const SegmentPair &b) { return a.i == b.i && a.j == b.j; }
    friend bool operator<(const SegmentPair &a, const SegmentPair &b)
    {
      return a.i < b.i || (a.i == b.i && a.j < b.j);
    }
  };

  class BroadPhase
  {
  public:
    /// diameter: contact distance of centrelines (d); skin > 0: Verlet skin
    /// (units d); exclusion >= 1: neighbours along the wire never paired.
    BroadPhase(double diameter, double skin, int exclusion);

    /// Rebuilds the candidate list if needed; returns true if it did.
    bool update(const std::vector<core::Vec2> &x, int first_node, int last_node);

    /// Whether the candidates hold every pair of x closer than the
    /// diameter: they were built for these nodes and none has moved more
    /// than skin/2 since (what update() checks before it rebuilds).
    bool covers(const std::vector<core::Vec2> &x, int first_node, int last_node) const;

    /// Force a rebuild at the next update (e.g. after nodes were renumbered).
    void invalidate() { valid = false; }

    /// Candidates, sorted by (i, j).
    const std::vector<SegmentPair> &candidates() const { return pairs; }
    unsigned int n_rebuilds() const { return rebuilds; }

    /// All pairs closer than `cutoff` and more than `exclusion` apart, by
    /// checking every pair: the reference for tests. Sorted by (i, j).
    static std::vector<SegmentPair> brute_force(const std::vector<core::Vec2> &x, int first_node,
                                                int last_node, double cutoff, int exclusion);

  private:
    void rebuild(const std::vector<core::Vec2> &x, int first_node, int last_node);

    double diameter;
    double skin;
    int exclusion;
    bool valid = false;
    int built_first = 0;
    int built_last = 0;
    std::vector<core::Vec2> x_at_build; // indexed like x
    std::vector<SegmentPair> pairs;
    unsigned int rebuilds = 0;
  };
} // namespace wirefem::contact
