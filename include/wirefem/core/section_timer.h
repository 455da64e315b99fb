#pragma once
/// Wall time per named section of a hot loop, read from the steady clock.
/// deal.II's TimerOutput also reads the process's CPU time (a getrusage
/// system call) at every scope's start and end; in the rod FEM, with a
/// scope per assembly and per linear solve, that was 11% of a run's time.

#include <fmt/format.h>

#include <chrono>
#include <cstring>
#include <deque>
#include <ostream>
#include <string>

namespace wirefem::core
{
  class SectionTimer
  {
    struct Entry
    {
      const char *name;
      unsigned long calls = 0;
      double seconds = 0.0;
    };

  public:
    using Clock = std::chrono::steady_clock;

    /// Adds the wall time from its construction to its end to the section
    /// named (a string literal: sections are told apart by their text).
    class Scope
    {
    public:
      Scope(SectionTimer &timer, const char *name)
        : entry(timer.entry(name))
        , start(Clock::now())
      {
      }
      ~Scope()
      {
        entry.seconds += std::chrono::duration<double>(Clock::now() - start).count();
        ++entry.calls;
      }
      Scope(const Scope &) = delete;
      Scope &operator=(const Scope &) = delete;

    private:
      Entry &entry;
      Clock::time_point start;
    };

    /// A table of the sections in the order they first ran: calls, wall
    /// time and its share of the time since the timer was made.
    void print_summary(std::ostream &out) const
    {
      const double total = std::chrono::duration<double>(Clock::now() - made).count();
      const std::string rule = "+---------------------------------+-----------+------------+------------+\n";
      out << "\n"
          << rule
          << fmt::format("| {:<31} | {:>9} | {:>10} | {:>10} |\n", "Section", "no. calls", "wall time",
                         "% of total")
          << rule;
      for (const auto &e : entries)
        out << fmt::format("| {:<31} | {:>9} | {:>9.3g}s | {:>9.2g}% |\n", e.name, e.calls, e.seconds,
                           total > 0.0 ? 100.0 * e.seconds / total : 0.0);
      out << rule << fmt::format("(of {:.3g} s since the model was set up)\n", total);
    }

  private:
    Entry &entry(const char *name)
    {
      for (auto &e : entries)
        if (e.name == name || std::strcmp(e.name, name) == 0)
          return e;
      entries.push_back({name});
      return entries.back();
    }

    Clock::time_point made = Clock::now();
    std::deque<Entry> entries; // a deque: an entry stays put while others are added
  };
} // namespace wirefem::core
