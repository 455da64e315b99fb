#include <wirefem/io/progress.h>

#include <cstdio>
#include <iostream>
#include <unistd.h>

namespace wirefem::io
{
  Progress::Progress(const std::string &mode)
    : enabled(mode != "off")
    , terminal(mode == "on" || (mode == "auto" && isatty(fileno(stderr))))
    // In place: a few refreshes a second; as log lines: rarely enough that
    // a long run does not flood a CI log.
    , interval_s(terminal ? 0.25 : 10.0)
    , last(std::chrono::steady_clock::now())
  {
  }

  void Progress::update(const std::string &line)
  {
    if (!enabled)
      return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last).count() < interval_s)
      return;
    last = now;
    if (terminal)
      {
        std::cerr << "\r\033[K" << line << std::flush;
        shown = true;
      }
    else
      std::cerr << line << '\n';
  }

  void Progress::finish()
  {
    if (terminal && shown)
      std::cerr << '\n';
    shown = false;
  }
} // namespace wirefem::io
