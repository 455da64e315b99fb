// Pictures of the wire in the cavity, as in the paper's Fig. 1 and Fig. 4:
// line thickness grows with the contact force, grey level with the local
// elastic bending energy (darker = more energy). Drawn with cairo.
#pragma once

#include <wirefem/analysis/wire_state.h>

#include <string>

namespace wirefem::io
{
  struct PictureOptions
  {
    int size_px = 1000;  ///< width and height of the PNG in pixels
    std::string caption; ///< one line drawn at the bottom-left, may be empty
  };

  /// Writes the same drawing to a PNG and an SVG file. Throws
  /// std::runtime_error if a file cannot be written.
  void write_pictures(const analysis::WireState &wire, const std::string &png_file,
                      const std::string &svg_file, const PictureOptions &options = {});
} // namespace wirefem::io
