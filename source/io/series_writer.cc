#include <wirefem/io/series_writer.h>

#include <iomanip>
#include <stdexcept>

namespace wirefem::io
{
  SeriesWriter::SeriesWriter(const std::string &filename, const std::vector<std::string> &columns,
                             const double resume_time)
    : n_columns(columns.size())
  {
    std::vector<std::string> kept;
    if (resume_time >= 0.0)
      {
        // Rows written after the checkpoint would be written again.
        std::ifstream in(filename);
        std::string line;
        std::getline(in, line); // header
        while (std::getline(in, line))
          if (!line.empty() && std::stod(line.substr(0, line.find(','))) <= resume_time)
            kept.push_back(line);
      }
    out.open(filename);
    if (!out)
      throw std::runtime_error("cannot write " + filename);
    for (std::size_t i = 0; i < columns.size(); ++i)
      out << (i ? "," : "") << columns[i];
    out << '\n';
    for (const auto &line : kept)
      out << line << '\n';
    out << std::setprecision(10);
  }

  void SeriesWriter::write_row(const std::vector<double> &values)
  {
    if (values.size() != n_columns)
      throw std::logic_error("series row has the wrong number of values");
    for (std::size_t i = 0; i < values.size(); ++i)
      out << (i ? "," : "") << values[i];
    out << '\n';
    out.flush();
  }
} // namespace wirefem::io
