// Channels anywhere on the cavity's wall, and the wire that starts between
// them. A channel is a straight guide of width d (the wire diameter) that
// meets the wall at its inlet, turned clockwise by an angle from the wall's
// inward normal there. Its mouth is the opening the channel cuts in the
// wall: the wall between the two corners where the channel's side walls,
// d/2 either side of its axis, meet it. Lengths in d.
#pragma once

#include <wirefem/core/vec2.h>
#include <wirefem/core/wire_state.h>
#include <wirefem/geometry/cavity.h>
#include <wirefem/injection/inlet.h>

#include <array>
#include <vector>

namespace wirefem::injection
{
  struct ChannelMouth
  {
    core::Vec2 inlet; ///< where the channel's axis meets the wall
    core::Vec2 axis;  ///< unit, along the channel into the cavity
    /// Where the side walls meet the wall: [0] on the left of the axis
    /// (looking into the cavity), [1] on its right.
    std::array<core::Vec2, 2> corners;
    /// Signed distances of the corners past the inlet along the axis.
    std::array<double, 2> corner_depth{};
    double half_width = 0.5;
    /// The chord between the corners, where the channel walls end: the
    /// point where it crosses the axis and its unit normal into the cavity.
    core::Vec2 cut_origin, cut_normal;

    /// Offset of a point across the axis (positive on its left).
    double across(const core::Vec2 &p) const { return core::cross(axis, p - inlet); }
    /// Distance of a point past the inlet along the axis.
    double along(const core::Vec2 &p) const { return core::dot(axis, p - inlet); }
  };

  /// The channel at `position` (a fraction of the wall's length from its
  /// start, counter-clockwise) turned clockwise by `angle` (radians, below
  /// pi/2) from the inward normal, `width` wide. Throws
  /// std::invalid_argument when its side walls do not meet the wall within
  /// a few widths of the inlet.
  ChannelMouth place_channel(const geometry::Cavity &cavity, double position, double angle, double width);

  /// A point's contact with the wall: how far its surface overlaps it and
  /// which way, with what the models need for the derivatives.
  struct WallTouch
  {
    double overlap = 0.0;
    core::Vec2 towards; ///< unit, from the point towards the wall
    /// Against a mouth's corner (the contact's direction is then from the
    /// point to `corner`), or against the wall (`spread` is then the
    /// derivative of `towards` along the wall's tangent t per displacement
    /// along t: d towards / dx = spread t t^T).
    bool at_corner = false;
    core::Vec2 corner;
    double spread = 0.0;
  };

  /// A point p of the wire's centreline (surface half_d away) against a
  /// mouth's corner: whether it overlaps it, by how much, and the unit
  /// vector from p towards the corner.
  bool touch_corner(const core::Vec2 &corner, const core::Vec2 &p, double half_d, double &overlap,
                    core::Vec2 &towards);

  /// Any cavity's wall with the channels' mouths cut in it (one or two): a point
  /// whose nearest wall point lies in a mouth, or that is in a channel
  /// behind its mouth, meets the mouth's nearer corner; any other point
  /// meets the wall. So the contact distance is continuous as the wire
  /// crosses a mouth.
  struct ChannelledWall
  {
    geometry::Cavity cavity;
    std::vector<ChannelMouth> mouths; ///< [0] the left channel, [1] the right one if any

    ChannelledWall(geometry::Cavity cavity, std::vector<ChannelMouth> mouths);
    /// Whether a point of the wire's centreline at p, the surface half_d
    /// away, overlaps the wall.
    bool touch(const core::Vec2 &p, double half_d, WallTouch &out) const;
    /// The wall as a polygon (about 1.3 points per d) and the channels, for
    /// pictures and analysis (core::WireState::wall, channels).
    void describe(core::WireState &w) const;
  };

  /// The initial wire between two channels: the cubic Bezier curve from the
  /// left inlet along its axis to the right inlet, arriving against the
  /// right channel's axis, with control points a third of the inlets'
  /// distance along the axes (a straight line when the channels face each
  /// other), by arc length. From one channel: the straight stub of a given
  /// length along its axis, ending free in the cavity.
  class InitialCurve
  {
  public:
    InitialCurve(const ChannelMouth &left, const ChannelMouth &right);
    InitialCurve(const ChannelMouth &channel, double stub_length);
    double length() const { return table.back(); }
    struct Point
    {
      core::Vec2 position;
      core::Vec2 normal; ///< unit, on the left of the direction of travel
    };
    /// The point at arc length s in [0, length()] from the left inlet.
    Point at(double s) const;
    /// The angle the tangent turns through from the left inlet to the right
    /// one (counter-clockwise positive; 0 for facing channels).
    double turning() const;
    /// The initial wire at arc length s: the curve's point moved across it
    /// by the seeded perturbation (injection/inlet.h, span length()).
    core::Vec2 perturbed(double s, const InitialShape &shape) const
    {
      const auto q = at(s);
      return q.position + shape.offset(s) * q.normal;
    }

  private:
    std::array<core::Vec2, 4> control;
    std::vector<double> table; ///< arc length at parameter k / (size - 1)
    void tabulate();
    core::Vec2 point(double u) const;
    core::Vec2 tangent(double u) const;
  };

  /// Half the length of the channel's axis across the cavity, from its
  /// inlet to where the axis meets the wall again: the free end of one
  /// channel's initial stub stops in the middle of that chord.
  double free_end_length(const geometry::Cavity &cavity, const ChannelMouth &channel);

  /// The initial wire of the wall's channels: the curve between two inlets;
  /// from one, the stub of free_end_length rounded to whole `unit`s (the
  /// model's element or segment length; 0 leaves it as it is).
  InitialCurve initial_curve(const ChannelledWall &wall, double unit);

  /// How much deeper in its channel, beyond the models' common margin, a
  /// channel must hold the wire (d units) so that no node leaves it where
  /// wire in the cavity already is: beside a tangential inlet at radius
  /// r_inlet that wire comes within d of the axis up to sqrt(2 r_inlet d)
  /// behind the inlet (plus d), and an oblique mouth (angle in degrees)
  /// reaches d tan(angle) further along its channel.
  double hold_beyond_mouth(bool tangential, double r_inlet, double diameter, double angle);

  /// The seeded perturbation (injection/inlet.h) across that curve: over its
  /// length between two channels; from one, over twice the stub's length,
  /// so that the stub's free end is where the first mode peaks.
  InitialShape initial_shape(unsigned int seed, double amplitude, double mirror_asymmetry,
                             const InitialCurve &curve, std::size_t n_channels);
} // namespace wirefem::injection
