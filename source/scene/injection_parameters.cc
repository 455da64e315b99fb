// The Injection section (declare, parse, validate side by side).
#include "declarations.h"

#include <cmath>

namespace wirefem::scene
{
  void InjectionParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    d.declare("Injection/Speed", "1", any_double,
              "Injection speed of each channel (d/time). 1 is 1/30 of the axial wave speed "
              "sqrt(EA/rho A) at the paper's values, so pushing is slow compared with stretching.");
    d.declare("Injection/Ramp time", "10", any_double,
              "Time over which the injection speed rises smoothly (1 - cos) from 0 to Speed: a sudden "
              "start would send a compression wave of force sqrt(EA rho A) * Speed into the wire.");
    d.declare("Injection/Slow start length", "0", any_double,
              "Length (d) each channel pushes at Slow start speed before the speed rises, by the same "
              "smooth ramp, to Speed. 0: no slow start. Lets the first arch grow quasi-statically to "
              "the wall (a straight wire pushed fast buckles into short waves instead).");
    d.declare("Injection/Slow start speed", "0.01", any_double,
              "Speed (d/time) of each channel during the slow start.");
    d.declare("Injection/Seed", "1", Patterns::Integer(0), "Seed of the symmetry-breaking perturbation.");
    d.declare("Injection/Perturbation", "0.5", any_double,
              "Amplitude (d) of the initial transverse perturbation: the clamped first buckling mode, "
              "up or down by the seed, plus random higher modes at a tenth of it.");
    d.declare("Injection/Mirror asymmetry", "1", any_double,
              "Scale of the perturbation's modes that are antisymmetric about the axis midway between "
              "the inlets: 1 as drawn by the seed, 0 a start with the mirror symmetry of the set-up "
              "(the up/down choice stays with the seed).");
    d.declare("Injection/Channels", "radial", Patterns::Selection("radial|tangential"),
              "radial: the paper's channels, on the x axis pointing at the centre, the wire starting "
              "straight across the cavity. tangential: channels along the wall at (-r', 0) and (r', 0) "
              "(r' = r - d/2), both pushing counter-clockwise, the wire starting as an S of two half "
              "circles between them; the geometry of the tight-spiral estimate (validation case 6).");
    d.declare("Injection/Maximum packing density", "0.6", any_double,
              "Stop at this phi = d L/(pi r^2) even if not jammed. Must exceed the initial 2d/(pi r).");
    d.declare("Injection/Jamming force", "50", any_double,
              "Jammed when the inlet force (mean of both, averaged over Jamming window) exceeds this. "
              "50 is 5% axial strain at EA = 1000: far above the loop-forming forces, below "
              "forces at which the penalty overlap matters.");
    d.declare("Injection/Jamming window", "1", any_double,
              "Injected length (d) over which the inlet force is averaged for the jamming test.");
    d.declare("Injection/Maximum time", "inf", Patterns::Anything(), "Stop at this time ('inf': no limit).");
  }

  void InjectionParameters::parse(const Declarations &d, const std::string &where)
  {
    speed = d.get_double("Injection/Speed");
    ramp_time = d.get_double("Injection/Ramp time");
    slow_start_length = d.get_double("Injection/Slow start length");
    slow_start_speed = d.get_double("Injection/Slow start speed");
    seed = static_cast<unsigned int>(std::stoul(d.get("Injection/Seed")));
    perturbation = d.get_double("Injection/Perturbation");
    mirror_asymmetry = d.get_double("Injection/Mirror asymmetry");
    tangential_channels = d.get("Injection/Channels") == "tangential";
    maximum_packing_density = d.get_double("Injection/Maximum packing density");
    jamming_force = d.get_double("Injection/Jamming force");
    jamming_window = d.get_double("Injection/Jamming window");
    const std::string t_max = d.get("Injection/Maximum time");
    try
      {
        maximum_time = t_max == "inf" ? INFINITY : std::stod(t_max);
      }
    catch (const std::exception &)
      {
        check(false, where, "Injection/Maximum time", "'" + t_max + "' is not a number or 'inf'");
      }
  }

  void InjectionParameters::validate(const std::string &w, const double radius) const
  {
    check(speed > 0, w, "Injection/Speed", "must be positive");
    check(ramp_time >= 0, w, "Injection/Ramp time", "must not be negative");
    check(slow_start_length >= 0, w, "Injection/Slow start length", "must not be negative");
    if (slow_start_length > 0)
      {
        check(slow_start_speed > 0, w, "Injection/Slow start speed", "must be positive");
        check(slow_start_length >= 0.5 * slow_start_speed * ramp_time, w, "Injection/Slow start length",
              "must be at least what the ramp injects, Slow start speed * Ramp time / 2");
      }
    check(perturbation >= 0, w, "Injection/Perturbation", "must not be negative");
    check(mirror_asymmetry >= 0, w, "Injection/Mirror asymmetry", "must not be negative");
    // The initial wire: straight across (2 r), or the S between tangential
    // inlets (pi (r - d/2)).
    const double l0 = tangential_channels ? M_PI * (radius - 0.5) : 2.0 * radius;
    const double phi0 = l0 / (M_PI * radius * radius);
    check(maximum_packing_density > phi0, w, "Injection/Maximum packing density",
          "must exceed the initial packing density " + std::to_string(phi0));
    check(maximum_packing_density <= 1.0, w, "Injection/Maximum packing density", "must not exceed 1");
    check(jamming_force > 0, w, "Injection/Jamming force", "must be positive");
    check(jamming_window > 0, w, "Injection/Jamming window", "must be positive");
    check(maximum_time > 0, w, "Injection/Maximum time", "must be positive");
  }
} // namespace wirefem::scene
