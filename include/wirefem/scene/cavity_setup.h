// The scene's cavity wall and channels as geometry: both models and the
// scene's checks build them here, from the Cavity and Injection keys.
#pragma once

#include <wirefem/geometry/cavity.h>
#include <wirefem/injection/channel_placement.h>
#include <wirefem/scene/parameters.h>

#include <memory>
#include <vector>

namespace wirefem::scene
{
  /// Whether the scene's cavity or channels differ from the paper's circle
  /// with its channels on the x axis (radial, or tangential): then the
  /// models use the general wall (geometry::Cavity) instead of the circle's
  /// closed form.
  bool general_wall(const CavityParameters &cavity, const InjectionParameters &injection);

  /// The wall, of area pi r^2 (parameters.h). Throws std::invalid_argument
  /// naming the fault of a polygon.
  geometry::Cavity cavity_wall(const CavityParameters &cavity);

  /// The arc length (counter-clockwise from geometry::Cavity::at's start)
  /// of the wall point where the +x axis from the centroid meets the wall.
  double wall_start(const geometry::Cavity &wall);

  /// The channels on that wall, [0] the left one, [1] the right one (if
  /// Injection/Channel positions names two), each one wire diameter wide,
  /// at those positions counted from wall_start. Throws
  /// std::invalid_argument.
  std::vector<injection::ChannelMouth> channel_mouths(const geometry::Cavity &wall,
                                                      const InjectionParameters &injection);

  /// The wall with the channels' mouths cut in it, as both models hold it.
  std::shared_ptr<const injection::ChannelledWall> channelled_wall(const CavityParameters &cavity,
                                                                   const InjectionParameters &injection);
} // namespace wirefem::scene
