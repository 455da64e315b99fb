// The benchmark set-ups' sections: Cantilever and Capstan (declare, parse,
// validate side by side).
#include "declarations.h"

#include <deal.II/base/utilities.h>

#include <cmath>

namespace wirefem::scene
{
  void CapstanParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Capstan/Wrap angle", "1.5707963267948966", any_double,
              "Angle (rad) the frictional part of the wire covers on the wall, centred on the top of "
              "the cavity; rounded to whole segments (summary.json has the angle used). At most 2.8.");
    d.declare("Capstan/End force", "1", any_double,
              "T0 (force): compressive follower force on the leading end, resisting the push.");
    d.declare("Capstan/Control", "velocity", Patterns::Selection("velocity|force"),
              "'velocity': the trailing end slides along the wall at Speed and the push force is "
              "measured (steady sliding: T0 exp(mu_d angle)). 'force': a compressive follower force on "
              "the trailing end rises at Force rate until the wire slips (T0 exp(mu_st angle)).");
    d.declare("Capstan/Speed", "0.05", any_double,
              "Velocity control: push speed (d/time); above Contact/Friction/Threshold velocity.");
    d.declare("Capstan/Ramp time", "50", any_double,
              "The end force T0 (and the speed, or the push force) rises linearly from 0 over this time.");
    d.declare("Capstan/Slide", "10", any_double,
              "Velocity control: distance pushed (d). The push force is averaged over the second half of "
              "the time after the ramp.");
    d.declare("Capstan/Force rate", "1e-3", any_double,
              "Force control: rate of rise of the push force, in units of End force per time.");
    d.declare("Capstan/Trailing end", "roller", Patterns::Selection("roller|clamped"),
              "Velocity control: how the pushed end is held. 'roller': its direction and polar angle are "
              "prescribed, its distance from the centre is free, so the wall carries the pressure next to "
              "it (a wire in a channel); 'clamped': its position too (the support then takes the wall "
              "pressure of a boundary layer of length (EI/k_n)^(1/4), and its friction).");
    d.declare("Capstan/Slip distance", "0.01", any_double,
              "Force control: the wire has slipped once its leading end moved this far (d).");
    d.declare("Capstan/Maximum time", "1e6", any_double,
              "Stop with exit status 3 when the run has not ended by this time.");
  }

  void CapstanParameters::parse(const Declarations &d)
  {
    wrap_angle = d.get_double("Capstan/Wrap angle");
    end_force = d.get_double("Capstan/End force");
    velocity_control = d.get("Capstan/Control") == "velocity";
    speed = d.get_double("Capstan/Speed");
    ramp_time = d.get_double("Capstan/Ramp time");
    slide = d.get_double("Capstan/Slide");
    force_rate = d.get_double("Capstan/Force rate");
    slip_distance = d.get_double("Capstan/Slip distance");
    trailing_roller = d.get("Capstan/Trailing end") == "roller";
    maximum_time = d.get_double("Capstan/Maximum time");
  }

  void CapstanParameters::validate(const std::string &w) const
  {
    check(wrap_angle > 0 && wrap_angle <= 2.8, w, "Capstan/Wrap angle",
          "must be in (0, 2.8] (the wire must stay clear of the channel openings)");
    check(end_force > 0, w, "Capstan/End force", "must be positive");
    check(speed > 0, w, "Capstan/Speed", "must be positive");
    check(ramp_time >= 0, w, "Capstan/Ramp time", "must not be negative");
    check(slide >= speed * ramp_time, w, "Capstan/Slide",
          "must be at least Speed * Ramp time (the push force is averaged over the second half of the "
          "sliding at full speed)");
    check(force_rate > 0, w, "Capstan/Force rate", "must be positive");
    check(slip_distance > 0, w, "Capstan/Slip distance", "must be positive");
    check(maximum_time > 0, w, "Capstan/Maximum time", "must be positive");
  }

  void CantileverParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Cantilever/Length", "20", any_double, "Rod length L (d), along +x from the clamp.");
    d.declare("Cantilever/End force x", "0", any_double, "Dead force on the free end, x (force).");
    d.declare("Cantilever/End force y", "0", any_double, "Dead force on the free end, y (force).");
    d.declare("Cantilever/End moment", "0", any_double,
              "Moment on the free end (force d), positive counter-clockwise.");
    d.declare("Cantilever/Load time", "100", any_double,
              "The load rises linearly from zero over this time; then the run relaxes to equilibrium.");
    d.declare("Cantilever/Load history", "1", Patterns::List(Patterns::Double(), 1),
              "Load factors the end load passes through, each reached linearly over Load time from the "
              "previous one (from 0 at the start): '1' loads once, '1, -1, 1' cycles. The run relaxes to "
              "equilibrium at the end of each leg (and at Points per leg along it) and writes them to "
              "history.csv.");
    d.declare("Cantilever/Points per leg", "1", Patterns::Integer(1, 10000),
              "Equilibria recorded along each leg of the load history.");
    d.declare("Cantilever/Damping", "0", any_double,
              "gamma of the relaxation drag -gamma m v (1/time); 0: twice the first bending frequency "
              "of the unloaded cantilever (critical damping of that mode).");
    d.declare("Cantilever/Tolerance", "1e-10", any_double,
              "Equilibrium: the largest nodal force below this times EI/L^2 + |F| + |M|/L.");
    d.declare("Cantilever/Maximum time", "1e6", any_double,
              "Stop with exit status 3 when not in equilibrium by this time.");
  }

  void CantileverParameters::parse(const Declarations &d)
  {
    length = d.get_double("Cantilever/Length");
    end_force_x = d.get_double("Cantilever/End force x");
    end_force_y = d.get_double("Cantilever/End force y");
    end_moment = d.get_double("Cantilever/End moment");
    load_time = d.get_double("Cantilever/Load time");
    load_history.clear();
    for (const auto &item : dealii::Utilities::split_string_list(d.get("Cantilever/Load history")))
      load_history.push_back(std::stod(item));
    points_per_leg = static_cast<unsigned int>(std::stoul(d.get("Cantilever/Points per leg")));
    damping = d.get_double("Cantilever/Damping");
    tolerance = d.get_double("Cantilever/Tolerance");
    maximum_time = d.get_double("Cantilever/Maximum time");
  }

  void CantileverParameters::validate(const std::string &w) const
  {
    check(length > 0, w, "Cantilever/Length", "must be positive");
    check(load_time >= 0, w, "Cantilever/Load time", "must not be negative");
    check(damping >= 0, w, "Cantilever/Damping", "must not be negative");
    check(tolerance > 0, w, "Cantilever/Tolerance", "must be positive");
    check(maximum_time > load_time, w, "Cantilever/Maximum time", "must exceed the load time");
  }
} // namespace wirefem::scene
