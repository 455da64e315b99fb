// The wire state that every model hands to analysis and io. Nothing downstream
// of this struct knows which model produced it.
//
// Units: lengths in wire diameters d, forces in the force unit of the scene
// (EA and EI are given in it), energies in force * d.
#pragma once

#include <wirefem/core/vec2.h>

#include <vector>

namespace wirefem::core
{
  /// One wire-wire contact: two points of the centreline closer than d.
  struct SelfContact
  {
    /// Rest arc-length coordinates of the two contact points, measured from the
    /// left end of the wire state (units d), s_a < s_b.
    double s_a = 0.0;
    double s_b = 0.0;
    /// Indices of the points of WireState::points nearest to each contact point.
    int point_a = 0;
    int point_b = 0;
    /// Contact points on the two centrelines (units d).
    core::Vec2 x_a;
    core::Vec2 x_b;
    /// Normal contact force magnitude (>= 0).
    double normal_force = 0.0;
  };

  /// A polyline wire from the left inlet to the right inlet, with per-point
  /// fields. All per-point vectors have points.size() entries.
  struct WireState
  {
    double diameter = 1.0;      ///< wire diameter d (the length unit, so 1)
    double cavity_radius = 1.0; ///< r, units d: the cavity's area is pi r^2
    /// The wall as a closed polygon (counter-clockwise, units d) when the
    /// cavity is not the circle of radius r about the origin; empty when it is.
    std::vector<core::Vec2> wall;
    /// With `wall`: each channel's inlet on the wall and its unit axis into
    /// the cavity, the left channel first.
    struct Channel
    {
      core::Vec2 inlet, axis;
    };
    std::vector<Channel> channels;
    double time = 0.0;
    double injected_length = 0.0; ///< wire length inside the cavity L (units d)

    std::vector<core::Vec2> points;        ///< centreline, left inlet to right inlet
    std::vector<double> arc_length;        ///< rest arc length from the first point (d)
    std::vector<double> curvature;         ///< signed curvature (1/d), + = turning left
    std::vector<double> plastic_curvature; ///< plastic (permanent) curvature (1/d)
    std::vector<double> bending_energy;    ///< elastic bending energy lumped at the point
    std::vector<double> contact_force;     ///< sum of contact normal forces at the point
    std::vector<SelfContact> self_contacts;
    double max_wall_force = 0.0; ///< largest wall contact force

    /// n points, with every per-point field zero.
    void resize(const std::size_t n)
    {
      points.assign(n, core::Vec2{});
      arc_length.assign(n, 0.0);
      curvature.assign(n, 0.0);
      plastic_curvature.assign(n, 0.0);
      bending_energy.assign(n, 0.0);
      contact_force.assign(n, 0.0);
    }
  };
} // namespace wirefem::core
