#include <wirefem/io/series_writer.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace wirefem::io
{
  SeriesWriter::SeriesWriter(const std::string &filename, const std::vector<std::string> &columns,
                             const double resume_time)
    : n_columns(columns.size())
  {
    std::string header;
    for (std::size_t i = 0; i < columns.size(); ++i)
      header += (i ? "," : "") + columns[i];
    std::vector<std::string> kept;
    if (resume_time >= 0.0)
      {
        // Rows written after the checkpoint would be written again. Times
        // are printed to 10 digits, so a row written at the checkpoint's
        // own step may read back a little later than it: compare within
        // that rounding (rows are a whole time step apart).
        const double rounding = 1e-9 * std::max(1.0, std::abs(resume_time));
        std::ifstream in(filename);
        std::string line;
        std::getline(in, line); // header
        // Rows of another column set would end up under this header.
        if (in && line != header)
          throw SeriesColumnsError(filename + ": its columns (" + line + ") are not this version's (" +
                                   header + "); resume the run with the version that started it");
        while (std::getline(in, line))
          if (!line.empty() && std::stod(line.substr(0, line.find(','))) <= resume_time + rounding)
            kept.push_back(line);
      }
    out.open(filename);
    if (!out)
      throw std::runtime_error("cannot write " + filename);
    out << header << '\n';
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

  std::vector<std::vector<double>> read_series_columns(const std::string &filename,
                                                       const std::vector<std::string> &names)
  {
    std::vector<std::vector<double>> columns(names.size());
    std::ifstream in(filename);
    std::string line;
    if (!std::getline(in, line))
      return columns;
    std::vector<int> index(names.size(), -1);
    {
      std::istringstream header(line);
      std::string name;
      for (int c = 0; std::getline(header, name, ','); ++c)
        for (std::size_t k = 0; k < names.size(); ++k)
          if (name == names[k])
            index[k] = c;
    }
    while (std::getline(in, line))
      {
        std::vector<double> row;
        std::istringstream fields(line);
        std::string field;
        while (std::getline(fields, field, ','))
          row.push_back(std::strtod(field.c_str(), nullptr));
        for (std::size_t k = 0; k < names.size(); ++k)
          if (index[k] >= 0 && index[k] < static_cast<int>(row.size()))
            columns[k].push_back(row[index[k]]);
      }
    return columns;
  }
} // namespace wirefem::io
