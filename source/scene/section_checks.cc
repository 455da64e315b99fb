// What the sections' key tables (scene/keys/*.json) cannot express:
// defaults derived from other keys (`resolve`) and checks that involve more
// than one key's range (`validate`).
#include "declarations.h"

#include <wirefem/injection/inlet.h>
#include <wirefem/scene/cavity_setup.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wirefem::scene
{
  void CavityParameters::validate(const std::string &w) const
  {
    check(radius > 1.0, w, "Cavity/Radius", "must be larger than 1 (the wire diameter)");
    check(shape != CavityShape::ellipse || aspect_ratio >= 1.0, w, "Cavity/Aspect ratio",
          "must be at least 1 (the long axis is along x)");
    // The wall bends nowhere tighter than the wire's diameter, so a point
    // in contact is never beyond its centre of curvature: at the ends of
    // the long axis b^2/a = r q^(-3/2) >= d.
    check(shape != CavityShape::ellipse || radius * std::pow(aspect_ratio, -1.5) >= 1.0, w,
          "Cavity/Aspect ratio",
          fmt::format("q = {:g} bends the wall tighter than d at the ends of the long axis (radius of "
                      "curvature r q^(-3/2) = {:.3g}); at most r^(2/3) = {:.3g}",
                      aspect_ratio, radius * std::pow(aspect_ratio, -1.5), std::pow(radius, 2.0 / 3.0)));
    check(shape != CavityShape::polygon || corner_radius >= 1.0, w, "Cavity/Corner radius",
          "must be at least 1 (the wire's diameter): the wall may bend no tighter than the wire");
  }

  namespace
  {
    /// The polygon's fault names the key it comes from.
    geometry::Cavity checked_wall(const CavityParameters &c, const std::string &w)
    {
      try
        {
          return cavity_wall(c);
        }
      catch (const std::invalid_argument &e)
        {
          const std::string why = e.what();
          throw InputError(
              w + ": " +
              (why.find("corner radius") != std::string::npos ? "Cavity/Corner radius" : "Cavity/Vertices") +
              ": " + why);
        }
    }
  } // namespace

  namespace
  {
    /// The mouths apart, and each channel outside the cavity behind its
    /// mouth (in a polygon that is not convex the line behind an inlet can
    /// cross another arm of the cavity).
    void check_mouths(const geometry::Cavity &wall, const std::vector<injection::ChannelMouth> &mouths,
                      const std::string &w)
    {
      if (mouths.size() == 2)
        {
          const double gap = core::norm(mouths[1].inlet - mouths[0].inlet);
          double corners = gap;
          for (const auto &a : mouths[0].corners)
            for (const auto &b : mouths[1].corners)
              corners = std::min(corners, core::norm(a - b));
          check(gap >= 4.0 && corners >= 1.0, w, "Injection/Channel positions",
                fmt::format("the channels overlap or nearly so: their inlets are {:.3g} d apart (at least "
                            "4 d needed), their mouths' corners {:.3g} d (at least 1 d)",
                            gap, corners));
        }
      const double back = 2.0 * std::sqrt(wall.area() / M_PI);
      for (const auto &m : mouths)
        {
          const double behind = std::min(m.corner_depth[0], m.corner_depth[1]) - 0.1;
          for (int k = 0; k <= 400; ++k)
            for (const double side : {-1.0, 0.0, 1.0})
              {
                const auto q = m.inlet + (behind - back * k / 400.0) * m.axis +
                               (side * m.half_width) * core::perp(m.axis);
                check(wall.nearest(q).depth < 0.0, w, "Injection/Channel positions",
                      fmt::format("the channel at ({:.3g}, {:.3g}) runs back through the cavity near "
                                  "({:.3g}, {:.3g})",
                                  m.inlet.x, m.inlet.y, q.x, q.y));
              }
        }
    }

    /// The initial wire, with its seeded perturbation, clear of the wall
    /// and of the mouths' corners, and its packing density below the
    /// largest.
    void check_initial_wire(const geometry::Cavity &wall, const std::vector<injection::ChannelMouth> &mouths,
                            const InjectionParameters &in, const double unit, const std::string &w)
    {
      const injection::ChannelledWall walled(wall, mouths);
      // One channel's stub as the model rounds it.
      const auto curve = [&] {
        try
          {
            return injection::initial_curve(walled, unit);
          }
        catch (const std::invalid_argument &e)
          {
            throw InputError(w + ": Injection/Channel positions: " + e.what());
          }
      }();
      const auto shape =
          injection::initial_shape(in.seed, in.perturbation, in.mirror_asymmetry, curve, mouths.size());
      // (Beside an oblique mouth the channel's axis passes within a few
      // thousandths of d of a corner's reach, so a start within 0.02 d of
      // it is let through: the contact takes it up in the first steps.)
      for (int k = 1; k < (mouths.size() == 2 ? 400 : 401); ++k)
        {
          const auto q = curve.perturbed(curve.length() * k / 400.0, shape);
          injection::WallTouch touch;
          const bool overlaps = walled.touch(q, 0.5, touch) && touch.overlap > 0.02;
          check(!overlaps, w, "Injection/Channel positions",
                fmt::format("the initial wire would overlap the wall by {:.2g} d near ({:.3g}, {:.3g})",
                            touch.overlap, q.x, q.y));
        }
      const double phi0 = curve.length() / wall.area();
      check(in.maximum_packing_density > phi0, w, "Injection/Maximum packing density",
            fmt::format("must exceed the initial packing density {:.4g}", phi0));
    }
  } // namespace

  void validate_wall(const Scene &s, const std::string &w)
  {
    const auto &in = s.injection;
    check(s.setup != Setup::capstan || s.cavity.shape == CavityShape::circle, w, "Cavity/Shape",
          "Set-up = capstan runs on the circle");
    if (s.setup != Setup::injection || !general_wall(s.cavity, in))
      return;
    check(
        !in.tangential_channels, w, "Injection/Channels",
        "'tangential' runs on the circle with the default Channel positions and angle; turn radial channels "
        "by Channel angle instead");
    const auto wall = checked_wall(s.cavity, w);
    const auto &p = in.channel_positions;
    check(p.size() == 1 || p.size() == 2, w, "Injection/Channel positions",
          fmt::format("needs one or two fractions (left, right channel), not {}", p.size()));
    for (const double x : p)
      check(x >= 0.0 && x < 1.0, w, "Injection/Channel positions",
            fmt::format("{:g} is off the wall: positions are fractions of its length in [0, 1)", x));
    check(in.channel_angle < 80.0, w, "Injection/Channel angle", "must be below 80 degrees");
    std::vector<injection::ChannelMouth> mouths;
    try
      {
        mouths = channel_mouths(wall, in);
      }
    catch (const std::invalid_argument &e)
      {
        throw InputError(
            w + ": Injection/Channel angle: " + e.what() +
            " (the wall curves away from the channel there: a smaller angle, or a flatter place)");
      }
    check_mouths(wall, mouths, w);
    const bool fem = s.model == ModelType::fem;
    check_initial_wire(wall, mouths, in, fem ? s.fem.element_length : s.discrete.segment_length, w);
    // Contact along the element checks points inside the elements only;
    // with one channel the wire's tip, a node, must meet wire and wall.
    check(p.size() == 2 || !fem || s.fem.contact_points == 0, w, "FEM/Contact points",
          "one channel (Injection/Channel positions) leaves the wire's tip free, which contact along the "
          "element does not reach: use 0 (node to segment)");
  }

  void ContactParameters::resolve()
  {
    // Negative coefficients stand for the defaults derived from the others.
    auto &f = friction;
    const double wall_static = f.wall_static_coefficient;
    const double wall_dynamic = f.wall_dynamic_coefficient;
    if (f.dynamic_coefficient < 0)
      f.dynamic_coefficient = 0.8 * f.static_coefficient;
    f.wall_static_coefficient = wall_static < 0 ? f.static_coefficient : wall_static;
    if (wall_dynamic < 0)
      f.wall_dynamic_coefficient = wall_static < 0 ? f.dynamic_coefficient : 0.8 * wall_static;
  }

  void ContactParameters::validate(const std::string &w) const
  {
    const auto &f = friction;
    check(f.dynamic_coefficient <= f.static_coefficient, w, "Contact/Friction/Dynamic coefficient",
          "mu_d = " + std::to_string(f.dynamic_coefficient) + " exceeds the static coefficient " +
              std::to_string(f.static_coefficient));
    check(f.wall_dynamic_coefficient <= f.wall_static_coefficient, w,
          "Contact/Friction/Wall dynamic coefficient", "exceeds the wall static coefficient");
  }

  void InjectionParameters::validate(const std::string &w, const double radius) const
  {
    if (slow_start_length > 0)
      {
        check(slow_start_speed > 0, w, "Injection/Slow start speed", "must be positive");
        check(slow_start_length >= 0.5 * slow_start_speed * ramp_time, w, "Injection/Slow start length",
              "must be at least what the ramp injects, Slow start speed * Ramp time / 2");
      }
    // The initial wire: straight across (2 r), or the S between tangential
    // inlets (pi (r - d/2)); one channel's stub is checked with the wall
    // (validate_wall).
    const double l0 = tangential_channels             ? M_PI * (radius - 0.5)
                      : channel_positions.size() == 1 ? 0.0
                                                      : 2.0 * radius;
    const double phi0 = l0 / (M_PI * radius * radius);
    check(maximum_packing_density > phi0, w, "Injection/Maximum packing density",
          "must exceed the initial packing density " + std::to_string(phi0));
    check(maximum_packing_density <= 1.0, w, "Injection/Maximum packing density", "must not exceed 1");
    check(maximum_time > 0, w, "Injection/Maximum time", "must be positive");
  }

  void CapstanParameters::validate(const std::string &w) const
  {
    check(wrap_angle > 0 && wrap_angle <= 2.8, w, "Capstan/Wrap angle",
          "must be in (0, 2.8] (the wire must stay clear of the channel openings)");
    check(slide >= speed * ramp_time, w, "Capstan/Slide",
          "must be at least Speed * Ramp time (the push force is averaged over the second half of the "
          "sliding at full speed)");
  }

  void CantileverParameters::validate(const std::string &w) const
  {
    check(maximum_time > load_time, w, "Cantilever/Maximum time", "must exceed the load time");
  }

  void FemParameters::resolve(const double axial_stiffness, const DiscreteParameters &discrete)
  {
    if (shear_stiffness < 0)
      shear_stiffness = 0.9 * axial_stiffness / 2.6;
    if (axial_viscosity < 0)
      axial_viscosity = discrete.axial_damping * discrete.segment_length;
    if (bending_viscosity < 0)
      bending_viscosity = discrete.rotational_damping * discrete.segment_length;
    // The springs need an implicit integrator and contact at the nodes;
    // with quasi-static steps they saved nothing (classic scene, f = 15).
    spring_self_friction = self_friction_law == SelfFrictionLaw::spring ||
                           (self_friction_law == SelfFrictionLaw::automatic &&
                            integrator == Integrator::generalized_alpha && contact_points == 0);
    // Modified Newton keeps LU factors of its own: auto leaves them to it.
    if (modified_newton && linear_solver == LinearSolver::automatic)
      linear_solver = LinearSolver::refactorise;
    // GMRES on kept factors solves almost exactly in a few iterations; on
    // the band, an inexact Newton step is cheaper.
    const bool band = linear_solver == LinearSolver::band || linear_solver == LinearSolver::automatic;
    if (linear_tolerance == 0.0)
      linear_tolerance = band ? 1e-3 : 1e-9;
    if (krylov_iterations == 0)
      krylov_iterations = band ? 30 : 8;
  }
} // namespace wirefem::scene
