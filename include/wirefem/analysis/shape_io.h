// Wire shapes from outside a run: a CSV file (a wire digitised from a
// photograph, say) or a run's output directory; and the analysis report of
// `wirefem analyze`.
#pragma once

#include <wirefem/core/input_error.h>
#include <wirefem/core/wire_state.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace wirefem::analysis
{
  /// Unreadable or malformed input: the message names the file (and line).
  using ShapeError = core::InputError;

  /// What the caller knows about a shape beyond its points.
  struct ShapeOptions
  {
    std::optional<double> diameter;      ///< wire diameter, in the units of the file
    std::optional<double> cavity_radius; ///< in the units of the file
  };

  /// A CSV shape: one point `x,y` per row in arc-length order; a header row
  /// and lines starting with '#' are skipped, except `# diameter = D` and
  /// `# radius = R`, which give those (options take precedence). Lengths are
  /// rescaled to units of the wire diameter (1 when none is given). Rest
  /// arc lengths are the lengths along the polyline; curvature is the
  /// turning angle at a point over the mean of its two segments.
  core::WireState read_shape_csv(const std::string &file, const ShapeOptions &options);

  /// The final state of a run: the last file listed in DIR/wire.pvd, and
  /// the cavity radius (or the options') and injected length from
  /// DIR/summary.json.
  core::WireState read_run_directory(const std::string &dir, const ShapeOptions &options);

  /// Reads either of the two, by what `path` is.
  core::WireState read_shape(const std::string &path, const ShapeOptions &options);

  /// Loops, morphology, symmetry and phi of a shape as JSON text. Without
  /// a cavity radius, phi and the morphology are null. Self-contacts are
  /// found from the geometry when the shape has none.
  std::string analysis_report(core::WireState wire, bool has_radius);
} // namespace wirefem::analysis
