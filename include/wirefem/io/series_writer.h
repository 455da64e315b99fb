// series.csv: one row per output step, a fixed set of named columns.
#pragma once

#include <wirefem/core/input_error.h>

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirefem::io
{
  /// Resuming onto a series.csv that is not the one the checkpoint
  /// continues: other columns, fewer rows, a damaged row.
  using SeriesResumeError = core::InputError;

  class SeriesWriter
  {
  public:
    /// resume_time >= 0: a resumed run. The existing file must hold
    /// exactly `resume_rows` rows up to that time (the rows the checkpoint
    /// counted), each a row of finite numbers; they are kept, later rows
    /// are cut, and new rows are appended. Otherwise SeriesResumeError is
    /// thrown and the file is left as it was. resume_time < 0: a new file.
    SeriesWriter(const std::string &filename, const std::vector<std::string> &columns,
                 double resume_time = -1.0, std::uint64_t resume_rows = 0);
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
