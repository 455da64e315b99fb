// Progress display: a one-line status rewritten in place on a terminal,
// periodic plain log lines otherwise (CI, files, pipes).
#pragma once

#include <chrono>
#include <string>

namespace wirefem::io
{
  class Progress
  {
  public:
    /// mode: "auto" (terminal detection on stderr), "on" or "off".
    explicit Progress(const std::string &mode);
    /// Shows the line if enough wall time passed since the last one.
    void update(const std::string &line);
    /// Ends an in-place line.
    void finish();

  private:
    bool enabled;
    bool terminal;
    double interval_s;
    std::chrono::steady_clock::time_point last;
    bool shown = false;
  };
} // namespace wirefem::io
