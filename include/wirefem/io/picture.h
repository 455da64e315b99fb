// Pictures of the wire in the cavity, as in the paper's Fig. 1 and Fig. 4:
// line thickness grows with the contact force, grey level with the local
// elastic bending energy (darker = more energy). Drawn with cairo.
#pragma once

#include <wirefem/core/wire_state.h>

#include <string>
#include <vector>

namespace wirefem::io
{
  struct PictureOptions
  {
    int size_px = 1000;               ///< width and height of the PNG in pixels
    std::string caption;              ///< one line drawn at the bottom-left, may be empty
    bool tangential_channels = false; ///< draw the channels along the wall (Injection/Channels)
  };

  /// Writes the same drawing to a PNG and an SVG file. Throws
  /// std::runtime_error if a file cannot be written.
  void write_pictures(const core::WireState &wire, const std::string &png_file, const std::string &svg_file,
                      const PictureOptions &options = {});

  /// The phase diagram of a sweep: one cell per (kappa_theta, mu_st), in
  /// the colour of its majority phase (paler when the majority is slim),
  /// with the votes it got out of its finished runs.
  struct PhaseDiagram
  {
    std::string title;
    std::vector<double> kappa; ///< rows, bottom to top
    std::vector<double> mu;    ///< columns, left to right
    struct Cell
    {
      std::string majority; ///< spiral | classic | plastic ("" without runs)
      double fraction = 0.0;
      int votes = 0;
      int runs = 0;
    };
    std::vector<Cell> cells; ///< row-major: cells[i * mu.size() + j]
  };

  /// Writes the diagram to a PNG and an SVG file (cairo).
  void write_phase_diagram(const PhaseDiagram &diagram, const std::string &png_file,
                           const std::string &svg_file);
} // namespace wirefem::io
