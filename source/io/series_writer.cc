#include <wirefem/io/series_writer.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace wirefem::io
{
  namespace
  {
    /// Whether `line` is a row of `n` numbers (inf and nan are numbers the
    /// writer may print, as curvature_ratio's inf) with a finite time.
    bool parse_row(const std::string &line, const std::size_t n, double &time)
    {
      std::size_t fields = 0, at = 0;
      while (at <= line.size())
        {
          const auto comma = std::min(line.find(',', at), line.size());
          const std::string field = line.substr(at, comma - at);
          char *end = nullptr;
          const double x = std::strtod(field.c_str(), &end);
          if (field.empty() || end != field.c_str() + field.size() || (fields == 0 && !std::isfinite(x)))
            return false;
          if (fields++ == 0)
            time = x;
          at = comma + 1;
        }
      return fields == n;
    }
  } // namespace

  SeriesWriter::SeriesWriter(const std::string &filename, const std::vector<std::string> &columns,
                             const double resume_time, const std::uint64_t resume_rows)
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
        const std::string refused = filename + ": cannot resume: ";
        std::ifstream in(filename);
        if (!in)
          throw SeriesResumeError(refused + "the file is missing; the checkpoint continues " +
                                  std::to_string(resume_rows) + " rows");
        std::string line;
        std::getline(in, line); // header
        // Rows of another column set would end up under this header.
        if (line != header)
          throw SeriesResumeError(refused + "its columns (" + line.substr(0, 200) +
                                  ") are not this version's (" + header +
                                  "); resume the run with the version that started it");
        for (std::size_t row = 1; std::getline(in, line); ++row)
          {
            double time = 0.0;
            if (!parse_row(line, n_columns, time))
              {
                if (kept.size() < resume_rows)
                  throw SeriesResumeError(refused + "row " + std::to_string(row) + " is damaged (not " +
                                          std::to_string(n_columns) + " numbers with a finite time)");
                break; // after the checkpoint's rows: cut with the rest
              }
            if (time > resume_time + rounding)
              break;
            kept.push_back(line);
          }
        if (kept.size() != resume_rows)
          throw SeriesResumeError(refused + "it has " + std::to_string(kept.size()) +
                                  " rows up to the checkpoint's time where the checkpoint counted " +
                                  std::to_string(resume_rows) + " (another run wrote it, or it was cut)");
      }
    // The kept rows are written next to the file and renamed over it, so an
    // interruption here leaves the file the checkpoint counted.
    const std::string tmp = filename + ".tmp";
    {
      std::ofstream fresh(resume_time >= 0.0 ? tmp : filename);
      fresh << header << '\n';
      for (const auto &line : kept)
        fresh << line << '\n';
      if (!fresh.flush())
        throw SeriesResumeError(filename + ": cannot write the file");
    }
    if (resume_time >= 0.0)
      std::filesystem::rename(tmp, filename);
    out.open(filename, std::ios::app);
    if (!out)
      throw SeriesResumeError(filename + ": cannot write the file");
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
