#include <wirefem/io/series_writer.h>

#include <iomanip>
#include <stdexcept>

namespace wirefem::io
{
  SeriesWriter::SeriesWriter(const std::string &filename, const std::vector<std::string> &columns)
    : out(filename)
    , n_columns(columns.size())
  {
    if (!out)
      throw std::runtime_error("cannot write " + filename);
    for (std::size_t i = 0; i < columns.size(); ++i)
      out << (i ? "," : "") << columns[i];
    out << '\n';
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
