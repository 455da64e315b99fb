#include <wirefem/contact/broad_phase.h>
#include <wirefem/contact/segment_distance.h>

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cassert>
#include <vector>

namespace wirefem::contact
{
  namespace
  {
    // The info is the segment's storage index. The explicit id policy keeps
    // ids stable under the copy that box_self_intersection_d makes of the
    // boxes, so no box is paired with itself and no pair is reported twice.
    using SegmentBox = CGAL::Box_intersection_d::Box_with_info_d<double, 2, int>;

    inline bool is_candidate(const std::vector<core::Vec2> &x, const int i, const int j, const double cutoff)
    {
      return closest_points(x[i], x[i + 1], x[j], x[j + 1]).distance < cutoff;
    }
  } // namespace

  BroadPhase::BroadPhase(const double diameter, const double skin, const int exclusion)
    : diameter(diameter)
    , skin(skin)
    , exclusion(exclusion)
  {
    assert(diameter > 0.0);
    assert(skin > 0.0);
    assert(exclusion >= 1);
  }

  bool BroadPhase::update(const std::vector<core::Vec2> &x, const int first_node, const int last_node)
  {
    assert(0 <= first_node && first_node <= last_node);
    assert(static_cast<std::size_t>(last_node) <= x.size());

    const bool needed = !covers(x, first_node, last_node);
    if (needed)
      rebuild(x, first_node, last_node);
    return needed;
  }

  bool BroadPhase::covers(const std::vector<core::Vec2> &x, const int first_node, const int last_node) const
  {
    if (!valid || first_node != built_first || last_node != built_last)
      return false;
    // Each node within skin/2 of its position at the last rebuild means any two
    // points of two segments approached each other by at most skin, so every
    // pair now closer than the diameter was closer than diameter + skin then.
    const double limit2 = 0.25 * skin * skin;
    for (int k = first_node; k < last_node; ++k)
      if (core::norm_square(x[k] - x_at_build[k]) > limit2)
        return false;
    return true;
  }

  void BroadPhase::rebuild(const std::vector<core::Vec2> &x, const int first_node, const int last_node)
  {
    const double cutoff = diameter + skin;
    const double r = 0.5 * cutoff;

    // Inactive entries are never read, so only the active range is copied.
    x_at_build.resize(x.size());
    std::copy(x.begin() + first_node, x.begin() + last_node, x_at_build.begin() + first_node);
    built_first = first_node;
    built_last = last_node;
    valid = true;
    ++rebuilds;
    pairs.clear();

    // Too few segments for any pair to pass the exclusion rule: skip the tree.
    if (last_node - first_node - 1 <= exclusion + 1)
      return;

    std::vector<SegmentBox> boxes;
    boxes.reserve(last_node - first_node - 1);
    for (int k = first_node; k + 1 < last_node; ++k)
      {
        const core::Vec2 &u = x[k];
        const core::Vec2 &v = x[k + 1];
        boxes.emplace_back(CGAL::Bbox_2(std::min(u.x, v.x) - r, std::min(u.y, v.y) - r,
                                        std::max(u.x, v.x) + r, std::max(u.y, v.y) + r),
                           k);
      }

    const int excl = exclusion;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const SegmentBox &a, const SegmentBox &b) {
      const int i = std::min(a.info(), b.info());
      const int j = std::max(a.info(), b.info());
      if (j - i > excl && is_candidate(x, i, j, cutoff))
        pairs.push_back({i, j});
    });

    // The tree reports pairs in no useful order; users and tests rely on (i, j).
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  }

  std::vector<SegmentPair> BroadPhase::brute_force(const std::vector<core::Vec2> &x, const int first_node,
                                                   const int last_node, const double cutoff,
                                                   const int exclusion)
  {
    assert(0 <= first_node && first_node <= last_node);
    assert(static_cast<std::size_t>(last_node) <= x.size());

    std::vector<SegmentPair> result;
    for (int i = first_node; i + 1 < last_node; ++i)
      for (int j = i + exclusion + 1; j + 1 < last_node; ++j)
        if (is_candidate(x, i, j, cutoff))
          result.push_back({i, j});
    return result;
  }
} // namespace wirefem::contact
