// ParaView output: one VTU (polyline, point data: curvature, plastic
// curvature, bending energy, contact force, arc length) per output step and a
// PVD collection that indexes them by time.
#pragma once

#include <wirefem/core/wire_state.h>

#include <string>
#include <utility>
#include <vector>

namespace wirefem::io
{
  /// Writes one ASCII VTU file of the wire. Throws std::runtime_error on failure.
  void write_vtu(const std::string &filename, const core::WireState &wire);

  /// A ParaView .pvd collection; write() rewrites the whole file atomically
  /// (temporary file + rename) so an interrupted run leaves a valid file.
  class PvdCollection
  {
  public:
    explicit PvdCollection(std::string pvd_filename);
    /// Records a VTU file (path relative to the .pvd file) at a time.
    void add(double time, const std::string &vtu_relative_path);
    void write() const;
    const std::vector<std::pair<double, std::string>> &entries() const { return records; }

  private:
    std::string filename;
    std::vector<std::pair<double, std::string>> records;
  };
} // namespace wirefem::io
