// The injection channels: at (-r, 0) pointing +x and at (r, 0) pointing
// -x (radial, the paper's set-up), or tangential: along the wall, at
// (-r', 0) pointing -y and at (r', 0) pointing +y with r' = r - d/2 the
// radius of the wire's centreline on the wall, so both push the wire round
// the wall counter-clockwise. Each pushes the wire in at the same speed: it rises smoothly from 0 to v
// over the ramp time T, v(t) = v (1 - cos(pi t/T))/2, and stays at v after, so
// the start sends no shock wave into the wire. Each channel has injected
//   u(t) = v (t/2 - T/(2 pi) sin(pi t/T))   for t < T,   v (t - T/2) after,
// and the wire inside the cavity is exactly L = L0 + 2 u(t), with L0 = 2 r
// (radial) or the rest length of the initial S between tangential inlets.
//
// Optional slow start: the first l0 per channel are pushed at v0 (ramped up
// as above), then the speed rises by the same smooth ramp from v0 to v. The
// schedule is the sum of two such ramps, the second (of height v - v0)
// starting at t1 = l0/v0 + T/2, when the first alone has injected l0; so
// u(t1) = l0 exactly (it needs l0 >= v0 T/2).
//
// A material point of the wire is labelled by its rest arc length S from the
// inlet at t = 0, negative while it is still in the channel; at time t it is
// at inlet + (S + u(t)) * axis as long as S + u(t) <= 0.
#pragma once

#include <wirefem/core/vec2.h>
#include <wirefem/injection/channel_placement.h>

#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace wirefem::injection
{
  enum class Side
  {
    left = 0,
    right = 1
  };

  class Channels
  {
  public:
    Channels(double radius, double speed, double ramp_time = 0.0, double slow_speed = 0.0,
             double slow_length = 0.0)
      : inlet_radius(radius)
      , initial_length_(2.0 * radius)
      , speed(slow_length > 0.0 ? slow_speed : speed)
      , ramp(ramp_time)
      , second_speed(slow_length > 0.0 ? speed - slow_speed : 0.0)
      , second_start(slow_length > 0.0 ? slow_length / slow_speed + 0.5 * ramp_time
                                       : std::numeric_limits<double>::infinity())
    {
    }

    /// Makes the channels tangential (see above): inlets at (-/+ r', 0),
    /// and L0 the wire's initial rest length inside the cavity.
    void make_tangential(double centreline_radius, double initial_length)
    {
      tangential = true;
      inlet_radius = centreline_radius;
      initial_length_ = initial_length;
      inlets = cut_origins = {{{-centreline_radius, 0.0}, {centreline_radius, 0.0}}};
      axes = cut_normals = {{{0.0, -1.0}, {0.0, 1.0}}};
      angles = {{-0.5 * M_PI, -0.5 * M_PI}};
    }
    /// Puts the channels anywhere (injection/channel_placement.h): each
    /// channel's inlet, axis and mouth; L0 the rest length of the initial
    /// wire between the inlets, and the angle its tangent turns through
    /// from the left inlet to the right one. With one mouth, the left
    /// channel alone pushes, the wire's other end is free, and L = L0 + u(t).
    void place(const std::vector<ChannelMouth> &mouths, double initial_length, double turning)
    {
      n_channels = static_cast<int>(mouths.size());
      for (int k = 0; k < n_channels; ++k)
        {
          inlets[k] = mouths[k].inlet;
          axes[k] = mouths[k].axis;
          cut_origins[k] = mouths[k].cut_origin;
          cut_normals[k] = mouths[k].cut_normal;
        }
      initial_length_ = initial_length;
      const double first = std::atan2(mouths[0].axis.y, mouths[0].axis.x);
      angles = {{first, first + turning}};
    }
    /// How many channels push: 2, or 1 (place()).
    int count() const { return n_channels; }
    bool pushes(Side s) const { return static_cast<int>(s) < n_channels; }
    bool is_tangential() const { return tangential; }
    /// Angle of the wire's tangent in both channels, taken along the wire
    /// from the left end to the right: 0 (radial) or -pi/2 (tangential).
    double wire_angle() const { return tangential ? -0.5 * M_PI : 0.0; }
    /// The same in channel s, for channels anywhere: the left channel's
    /// axis, and at the right one that angle plus the initial wire's turning
    /// (so the angle is continuous along the wire).
    double wire_angle(Side s) const { return angles[static_cast<int>(s)]; }

    /// A point of the tangential channels' initial S, at arc length s
    /// (0 <= s <= pi r') from the left inlet along its centreline, and the
    /// angle of the wire's tangent there.
    struct CurvePoint
    {
      core::Vec2 position;
      double angle;
    };
    /// The S from the left inlet, heading down, round the half circle of
    /// radius rho = r'/2 centred at (-rho, 0) to the centre, then round the
    /// one centred at (rho, 0) to the right inlet, arriving heading down:
    /// both arms leave their channels along the wall.
    CurvePoint initial_s(double s) const
    {
      const double rho = 0.5 * inlet_radius;
      const bool first_half = s < M_PI * rho;
      const double theta = first_half ? M_PI + s / rho : 2.0 * M_PI - s / rho;
      const double centre = first_half ? -rho : rho;
      return {{centre + rho * std::cos(theta), rho * std::sin(theta)},
              wire_angle() + (first_half ? s / rho : 2.0 * M_PI - s / rho)};
    }

    core::Vec2 inlet(Side s) const { return inlets[static_cast<int>(s)]; }
    /// Unit vector along which the channel pushes, into the cavity.
    core::Vec2 axis(Side s) const { return axes[static_cast<int>(s)]; }
    /// The mouth as the channel walls see it (ChannelTerm, the FEM's
    /// channel elements): the wire is in the channel where it lies behind
    /// the line through cut_origin (on the axis) normal to cut_normal. For
    /// the paper's channels the inlet and the axis; for channels anywhere
    /// the chord between the mouth's corners.
    core::Vec2 cut_origin(Side s) const { return cut_origins[static_cast<int>(s)]; }
    core::Vec2 cut_normal(Side s) const { return cut_normals[static_cast<int>(s)]; }

    /// Position at time t of the material point S of the wire in channel s.
    core::Vec2 position(Side s, double material_coordinate, double t) const
    {
      return inlet(s) + (material_coordinate + injected_per_channel(t)) * axis(s);
    }
    /// Signed distance of x past the inlet along the channel axis.
    double depth(Side s, const core::Vec2 &x) const
    {
      const auto a = axis(s);
      return (x.x - inlet(s).x) * a.x + (x.y - inlet(s).y) * a.y;
    }

    /// Speed of each channel at time t.
    double injection_speed(double t) const
    {
      return ramp_speed(speed, t) + (t > second_start ? ramp_speed(second_speed, t - second_start) : 0.0);
    }
    /// d(speed)/dt of each channel at time t.
    double injection_acceleration(double t) const
    {
      return ramp_acceleration(speed, t) +
             (t > second_start ? ramp_acceleration(second_speed, t - second_start) : 0.0);
    }
    /// Length u(t) injected by each channel.
    double injected_per_channel(double t) const
    {
      return ramp_length(speed, t) + (t > second_start ? ramp_length(second_speed, t - second_start) : 0.0);
    }
    /// Wire length inside the cavity, L = L0 + 2 u(t) (one channel: L0 + u(t)).
    double injected_length(double t) const { return initial_length_ + n_channels * injected_per_channel(t); }
    /// L0.
    double initial_length() const { return initial_length_; }

  private:
    // One smooth ramp from 0 to v over T, started at t = 0.
    double ramp_speed(double v, double t) const
    {
      return t < ramp ? 0.5 * v * (1.0 - std::cos(M_PI * t / ramp)) : v;
    }
    double ramp_acceleration(double v, double t) const
    {
      return t < ramp ? 0.5 * v * M_PI / ramp * std::sin(M_PI * t / ramp) : 0.0;
    }
    double ramp_length(double v, double t) const
    {
      return t < ramp ? v * (0.5 * t - ramp / (2.0 * M_PI) * std::sin(M_PI * t / ramp))
                      : v * (t - 0.5 * ramp);
    }

    bool tangential = false;
    int n_channels = 2;
    double inlet_radius; ///< distance of the inlets from the centre (radial, tangential)
    std::array<core::Vec2, 2> inlets{{{-inlet_radius, 0.0}, {inlet_radius, 0.0}}};
    std::array<core::Vec2, 2> axes{{{1.0, 0.0}, {-1.0, 0.0}}};
    std::array<double, 2> angles{{0.0, 0.0}}; ///< wire_angle(Side)
    std::array<core::Vec2, 2> cut_origins{inlets}, cut_normals{axes};
    double initial_length_; ///< L0
    double speed;           ///< of the first ramp: the slow start's, or the only one
    double ramp;
    double second_speed; ///< height of the second ramp (0 without a slow start)
    double second_start; ///< its start (infinite without a slow start)
  };
  /// Tangential channels: the wire's end nodes behind each inlet belong to
  /// the channels (their walls guide them), those of the left channel with
  /// y > 0 and of the right one with y < 0. Given the nodes [first, last)
  /// and their y(k), returns the range [b, e) of nodes in the cavity.
  template <typename YOfNode>
  std::pair<int, int> nodes_past_tangential_inlets(int first, int last, const YOfNode &y)
  {
    while (first < last && y(first) > 0.0)
      ++first;
    while (last > first && y(last - 1) < 0.0)
      --last;
    return {first, last};
  }
} // namespace wirefem::injection
