// series.csv: one row per output step, a fixed set of named columns.
#pragma once

#include <wirefem/core/input_error.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirefem::io
{
  /// Resuming onto a series.csv whose header is not this writer's columns.
  using SeriesColumnsError = core::InputError;

  class SeriesWriter
  {
  public:
    /// resume_time >= 0: keep the rows of an existing file up to that time
    /// (a resumed run) and append; otherwise start a new file.
    SeriesWriter(const std::string &filename, const std::vector<std::string> &columns,
                 double resume_time = -1.0);
    /// values in the order of the columns; flushed so an interrupted run keeps its rows.
    void write_row(const std::vector<double> &values);

  private:
    std::ofstream out;
    std::size_t n_columns;
  };

  /// The named columns of a series.csv (missing columns come back empty).
  std::vector<std::vector<double>> read_series_columns(const std::string &filename,
                                                       const std::vector<std::string> &names);
} // namespace wirefem::io
