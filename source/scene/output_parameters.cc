// The Output section (declare, parse, validate side by side).
#include "declarations.h"

#include <cmath>

namespace wirefem::scene
{
  void OutputParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Output/Directory", "", Patterns::Anything(),
              "Where all output goes. Empty: output/<scene name>.");
    d.declare("Output/Interval", "1", any_double, "Injected length (d) between rows of series.csv.");
    d.declare("Output/VTU interval", "20", any_double,
              "Injected length (d) between ParaView files; 0: only the final state.");
    d.declare("Output/Picture size", "1000", Patterns::Integer(100, 10000), "final.png size in pixels.");
    d.declare("Output/Progress", "auto", Patterns::Selection("auto|on|off"),
              "One-line progress display: auto = on a terminal, periodic log lines otherwise.");
    d.declare("Output/Checkpoint interval", "300", any_double,
              "Wall-clock seconds between checkpoints (checkpoint.bin, for --resume); 0: only when "
              "interrupted (SIGINT/SIGTERM).");
  }

  void OutputParameters::parse(const Declarations &d)
  {
    directory = d.get("Output/Directory");
    interval = d.get_double("Output/Interval");
    vtu_interval = d.get_double("Output/VTU interval");
    picture_size = std::stoi(d.get("Output/Picture size"));
    progress = d.get("Output/Progress");
    checkpoint_interval = d.get_double("Output/Checkpoint interval");
  }

  void OutputParameters::validate(const std::string &w) const
  {
    check(interval > 0, w, "Output/Interval", "must be positive");
    check(checkpoint_interval >= 0, w, "Output/Checkpoint interval", "must not be negative");
    check(vtu_interval >= 0, w, "Output/VTU interval", "must not be negative");
  }
} // namespace wirefem::scene
