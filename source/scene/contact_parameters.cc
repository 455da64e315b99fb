// The Contact section with its Friction subsection (declare, parse,
// validate side by side).
#include "declarations.h"

#include <cmath>

namespace wirefem::scene
{
  void ContactParameters::declare(Declarations &d)
  {
    const auto any_double = Patterns::Double();
    const auto boolean = Patterns::Bool();
    d.declare("Contact/Wall contact", "true", boolean, "Keep the wire surface inside the cavity.");
    d.declare("Contact/Self contact", "true", boolean, "Wire-wire contact.");
    d.declare("Contact/Normal stiffness", "2000", any_double,
              "Penalty k_n (force/d per d of wire): a wire on the wall is pressed back by "
              "k_n * overlap per unit length (README: Contact, for wire on wire).");
    d.declare("Contact/Skin", "0.5", any_double,
              "Verlet skin (d): candidates are refreshed once a node moved more than skin/2.");
    d.declare("Contact/Exclusion length", "3", any_double,
              "Segments closer than this arc length (d) along the wire never touch each other.");
    d.declare("Contact/Friction/Static coefficient", "0", any_double,
              "mu_st, wire-wire and (unless given) wire-wall.");
    d.declare("Contact/Friction/Dynamic coefficient", "-1", any_double,
              "mu_d <= mu_st. Negative: 0.8 * Static coefficient (the paper gives no value).");
    d.declare("Contact/Friction/Wall static coefficient", "-1", any_double,
              "mu_st at the wall. Negative: same as Static coefficient.");
    d.declare("Contact/Friction/Wall dynamic coefficient", "-1", any_double,
              "mu_d at the wall. Negative: 0.8 * Wall static coefficient.");
    d.declare("Contact/Friction/Threshold velocity", "0.01", any_double,
              "v_th (d/time): a sliding contact sticks again below this tangential speed.");
    d.declare("Contact/Friction/Tangential stiffness ratio", "0.2", any_double,
              "k_t/k_n of the spring that carries static friction while a contact sticks. 0.2 (close to "
              "the 2/7 of elastic spheres): stiffer springs raise the first-order time-stepping error of "
              "the energy balance at mu_st = 5 (1% at 0.5, 0.3% at 0.1 on the f = 25 classic scene).");
    d.declare("Contact/Friction/Surface torque", "false", boolean,
              "Discrete model: friction acts at the wire's surface, d/2 off the centreline, so it "
              "also turns the wire there (moment d/2 F_t on the node's segments) and the slip "
              "includes the surface's turning (d/2 times the rotation rate). false: at the "
              "centreline, as a point-mass chain has it.");
  }

  void ContactParameters::parse(const Declarations &d)
  {
    wall_contact = d.get_bool("Contact/Wall contact");
    self_contact = d.get_bool("Contact/Self contact");
    normal_stiffness = d.get_double("Contact/Normal stiffness");
    skin = d.get_double("Contact/Skin");
    exclusion_length = d.get_double("Contact/Exclusion length");
    // Negative coefficients stand for the defaults derived from the others.
    auto &f = friction;
    f.static_coefficient = d.get_double("Contact/Friction/Static coefficient");
    const double mud = d.get_double("Contact/Friction/Dynamic coefficient");
    f.dynamic_coefficient = mud < 0 ? 0.8 * f.static_coefficient : mud;
    const double wst = d.get_double("Contact/Friction/Wall static coefficient");
    f.wall_static_coefficient = wst < 0 ? f.static_coefficient : wst;
    const double wd = d.get_double("Contact/Friction/Wall dynamic coefficient");
    f.wall_dynamic_coefficient = wd < 0 ? (wst < 0 ? f.dynamic_coefficient : 0.8 * wst) : wd;
    f.threshold_velocity = d.get_double("Contact/Friction/Threshold velocity");
    f.tangential_stiffness_ratio = d.get_double("Contact/Friction/Tangential stiffness ratio");
    f.surface_torque = d.get_bool("Contact/Friction/Surface torque");
  }

  void ContactParameters::validate(const std::string &w) const
  {
    check(normal_stiffness > 0, w, "Contact/Normal stiffness", "must be positive");
    check(skin > 0, w, "Contact/Skin", "must be positive");
    check(exclusion_length >= 0, w, "Contact/Exclusion length", "must not be negative");
    const auto &f = friction;
    check(f.static_coefficient >= 0, w, "Contact/Friction/Static coefficient", "must not be negative");
    check(f.dynamic_coefficient >= 0, w, "Contact/Friction/Dynamic coefficient", "must not be negative");
    check(f.dynamic_coefficient <= f.static_coefficient, w, "Contact/Friction/Dynamic coefficient",
          "mu_d = " + std::to_string(f.dynamic_coefficient) + " exceeds the static coefficient " +
              std::to_string(f.static_coefficient));
    check(f.wall_dynamic_coefficient <= f.wall_static_coefficient, w,
          "Contact/Friction/Wall dynamic coefficient", "exceeds the wall static coefficient");
    check(f.threshold_velocity >= 0, w, "Contact/Friction/Threshold velocity", "must not be negative");
    check(f.tangential_stiffness_ratio > 0, w, "Contact/Friction/Tangential stiffness ratio",
          "must be positive");
  }
} // namespace wirefem::scene
