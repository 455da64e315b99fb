// ParaView output of the wire. ASCII rather than binary: the files are small
// (one polyline), diffable, and readable without a VTK installation.
//
// Each segment is its own VTK_LINE cell (type 3) rather than one poly-line
// cell: ParaView filters (Tube, Plot Over Line, cell-data conversion) then work
// per segment, and a segment can be picked and inspected on its own.

#include <wirefem/io/vtu_writer.h>

#include <cstdio>
#include <fstream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wirefem::io
{
  namespace
  {
    /// Enough digits that every double survives the round trip through text.
    constexpr int full_precision = std::numeric_limits<double>::max_digits10;

    constexpr int vtk_line = 3;

    /// File names go into an XML attribute; the characters that would end or
    /// break it are escaped.
    std::string xml_escape(const std::string &text)
    {
      std::string out;
      out.reserve(text.size());
      for (const char c : text)
        switch (c)
          {
          case '&':
            out += "&amp;";
            break;
          case '<':
            out += "&lt;";
            break;
          case '>':
            out += "&gt;";
            break;
          case '"':
            out += "&quot;";
            break;
          case '\'':
            out += "&apos;";
            break;
          default:
            out += c;
          }
      return out;
    }

    void write_point_array(std::ostream &out, const std::string &name, const std::vector<double> &values)
    {
      out << "        <DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < values.size(); ++i)
        out << (i % 6 == 0 ? "          " : " ") << values[i]
            << (i % 6 == 5 || i + 1 == values.size() ? "\n" : "");
      out << "        </DataArray>\n";
    }

    /// Closes the stream and turns any error during writing into an exception;
    /// a silently truncated output file would only be noticed in ParaView.
    void finish(std::ofstream &file, const std::string &filename, const char *function)
    {
      file.close();
      if (!file)
        throw std::runtime_error(std::string(function) + ": error writing '" + filename + "'");
    }
  } // namespace

  void write_vtu(const std::string &filename, const core::WireState &wire)
  {
    std::ofstream file(filename);
    if (!file)
      throw std::runtime_error("wirefem::io::write_vtu: cannot open '" + filename + "'");
    file.precision(full_precision);

    const std::size_t n_points = wire.points.size();
    const std::size_t n_cells = n_points < 2 ? 0 : n_points - 1;

    // Per-point fields that a model did not fill (or filled inconsistently)
    // are left out rather than padded: a made-up array would look real.
    const std::pair<const char *, const std::vector<double> *> fields[] = {
        {"arc_length", &wire.arc_length},
        {"curvature", &wire.curvature},
        {"plastic_curvature", &wire.plastic_curvature},
        {"bending_energy", &wire.bending_energy},
        {"contact_force", &wire.contact_force}};

    file << "<?xml version=\"1.0\"?>\n"
         << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         << "  <UnstructuredGrid>\n"
         // TimeValue is the field ParaView reads as the time of a lone file.
         << "    <FieldData>\n"
         << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
            "format=\"ascii\">"
         << wire.time << "</DataArray>\n"
         << "    </FieldData>\n"
         << "    <Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << n_cells << "\">\n"
         << "      <PointData>\n";
    for (const auto &[name, values] : fields)
      if (n_points > 0 && values->size() == n_points)
        write_point_array(file, name, *values);
    file << "      </PointData>\n"
         << "      <Points>\n"
         << "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto &p : wire.points)
      file << "          " << p.x << ' ' << p.y << " 0\n";
    file << "        </DataArray>\n"
         << "      </Points>\n"
         << "      <Cells>\n"
         << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (std::size_t k = 0; k < n_cells; ++k)
      file << "          " << k << ' ' << k + 1 << '\n';
    file << "        </DataArray>\n"
         << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t k = 0; k < n_cells; ++k)
      file << (k % 10 == 0 ? "          " : " ") << 2 * (k + 1)
           << (k % 10 == 9 || k + 1 == n_cells ? "\n" : "");
    file << "        </DataArray>\n"
         << "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t k = 0; k < n_cells; ++k)
      file << (k % 20 == 0 ? "          " : " ") << vtk_line
           << (k % 20 == 19 || k + 1 == n_cells ? "\n" : "");
    file << "        </DataArray>\n"
         << "      </Cells>\n"
         << "    </Piece>\n"
         << "  </UnstructuredGrid>\n"
         << "</VTKFile>\n";

    finish(file, filename, "wirefem::io::write_vtu");
  }

  PvdCollection::PvdCollection(std::string pvd_filename)
    : filename(std::move(pvd_filename))
  {
  }

  void PvdCollection::add(const double time, const std::string &vtu_relative_path)
  {
    records.emplace_back(time, vtu_relative_path);
  }

  void PvdCollection::write() const
  {
    const std::string tmp = filename + ".tmp";
    try
      {
        std::ofstream file(tmp);
        if (!file)
          throw std::runtime_error("wirefem::io::PvdCollection::write: cannot open '" + tmp + "'");
        file.precision(full_precision);

        file << "<?xml version=\"1.0\"?>\n"
             << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
             << "  <Collection>\n";
        for (const auto &[time, path] : records)
          file << "    <DataSet timestep=\"" << time << "\" group=\"\" part=\"0\" file=\"" << xml_escape(path)
               << "\"/>\n";
        file << "  </Collection>\n"
             << "</VTKFile>\n";
        finish(file, tmp, "wirefem::io::PvdCollection::write");
      }
    catch (...)
      {
        // Never leave a half-written temporary next to the valid old file.
        std::remove(tmp.c_str());
        throw;
      }

    // rename() replaces the target atomically on POSIX, so a reader sees
    // either the old or the new collection, never a partial one.
    if (std::rename(tmp.c_str(), filename.c_str()) != 0)
      {
        std::remove(tmp.c_str());
        throw std::runtime_error("wirefem::io::PvdCollection::write: cannot rename '" + tmp + "' to '" +
                                 filename + "'");
      }
  }
} // namespace wirefem::io
