// Penalty contact with regularised Coulomb friction for the rod FEM, with
// consistent linearisation. The contact geometry is the polyline through the
// mesh nodes (the support points of the elements); each contact acts on
// the nodes that carry it.
//
// Normal: a penalty k w g for the overlap g = d - distance (self contact) or
// g = |x| + d/2 - r (wall), with k the penalty per unit length and w the wire
// length the contact stands for. It is the gradient of the energy
// 1/2 k w g^2 (envelope theorem at the closest point).
//
// Friction: F_t = -mu(|v_t|) F_n tanh(v_t / v_th) along the contact tangent,
// mu(v) = mu_d + (mu_st - mu_d) exp(-|v| / v_th). Below v_th the law is a
// steep viscous branch that carries up to ~mu_st F_n (stick); above it the
// coefficient relaxes to mu_d (slip). The velocities are those of the time
// integrator, v = c x + v0 (c = d v / d x of the scheme), so the tangent
// includes the friction's velocity dependence.
//
// Residual convention: the returned vector is the contact's contribution to
// the internal force (minus the force on the nodes), and the tangent its
// derivative with respect to the node coordinates (x0, y0, x1, y1, ...).
// friction_scale weights the friction part in the tangent only (for time
// integrators that blend conservative forces but not dissipative ones).
#pragma once

#include <wirefem/contact/friction_law.h>
#include <wirefem/core/vec2.h>
#include <wirefem/injection/channel_placement.h>

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

namespace wirefem::fem
{
  struct ContactSettings
  {
    double diameter = 1.0;
    double stiffness = 2000.0; ///< k_n per unit length of wire
    bool friction = false;
    double mu_static = 0.0;
    double mu_dynamic = 0.0;
    double threshold_velocity = 0.01;
    /// The wall has the radial channels' mouths (see wall_contact); false
    /// for a closed circle (tangential channels).
    bool mouths = true;
    /// Any other cavity or channels off the x axis (scene::general_wall):
    /// the wall with its mouths, instead of the circle of radius r.
    std::shared_ptr<const injection::ChannelledWall> shaped;
  };

  /// Contribution of one contact on up to four points.
  struct ContactContribution
  {
    int n_points = 0;
    std::array<double, 8> residual{};          ///< normal + friction
    std::array<double, 8> friction_residual{}; ///< the friction part of residual
    /// d (residual + (friction_scale - 1) friction_residual) / d x, row major, 2 n_points square
    std::array<double, 64> tangent{};
    double overlap = 0.0;
    double normal_force = 0.0;
    double energy = 0.0; ///< 1/2 k w g^2
    /// Set by the caller: false leaves the tangent zero (an evaluation of
    /// the residual alone). The point contacts honour it.
    bool want_tangent = true;
  };

  /// The friction coefficient the regularised law mobilises when sliding at
  /// speed v: mu(v) tanh(v / v_th), from the law the contacts use.
  double sliding_coefficient(const ContactSettings &s, double v);

  /// The regularised law's v_th, kept above zero (v_th = 0 is Coulomb's
  /// law, which the regularisation only approaches).
  inline double regularised_threshold(const ContactSettings &s)
  {
    return std::max(s.threshold_velocity, 1e-9);
  }

  /// The regularised law's friction damping at rest, mu_st F_n / v_th: the
  /// slope of the friction force in the slip rate. An explicit step longer
  /// than (mass / damping) lets the friction of a contact overshoot.
  inline double friction_damping(const ContactSettings &s, const double fn)
  {
    return s.mu_static * fn / regularised_threshold(s);
  }

  /// Wall of the cavity: a circle of radius r, open over |y| < d/2 at x = +-r
  /// (the radial channels), where the corners of the openings are the
  /// contact; a closed circle when s.mouths is false; s.shaped when set.
  /// Returns false when the point does not touch.
  bool wall_contact(double radius, const ContactSettings &s, double weight, const core::Vec2 &x,
                    const core::Vec2 &v0, double c, ContactContribution &out, double friction_scale = 1.0);

  /// Friction state of a wall contact under the spring law.
  struct SpringFriction
  {
    contact::FrictionHistory history; ///< after this step (trial until committed)
    double dissipated = 0.0;          ///< over this step
    double stored = 0.0;              ///< in the spring after this step, 1/2 k_t u^2
  };

  /// One step of the discrete model's friction law (contact/friction_law.h)
  /// in displacements: a spring of stiffness kt from `old`, slipping by
  /// `slip` under the normal force fn. The cap is mu_st fn, or mu_d fn when
  /// `old` slides. Returns 0 while the spring holds, else the slide force's
  /// coefficient (+-mu_d, with the force's sign); fills the history after
  /// the step, the energy dissipated (the trapezoidal work of the force
  /// less what the spring stores) and the energy stored.
  double spring_step(const ContactSettings &s, double kt, double fn, double slip, double dt,
                     const contact::FrictionHistory &old, SpringFriction &friction);

  /// The wall with the discrete model's friction law (contact/friction_law.h)
  /// instead of the regularised one: a tangential spring of stiffness
  /// ratio * k w, elongated by the tangential part of x - x_old, capped at
  /// mu_st F_n while sticking and at mu_d F_n while sliding. As in an
  /// explicit step the cap is chosen from the state the step starts from:
  /// `sliding` is set by a step that hit the cap at a tangential speed
  /// |(x - x_old).t| / dt of at least v_th. So the contact holds exactly
  /// below the static limit: a sharp stick/slip threshold. The tangent is
  /// exact within the branch the current x is in.
  bool wall_contact_spring(double radius, const ContactSettings &s, double weight, double stiffness_ratio,
                           const core::Vec2 &x, const core::Vec2 &x_old, double dt,
                           const contact::FrictionHistory &old, ContactContribution &out,
                           SpringFriction &friction, double friction_scale = 1.0);
  /// The same by automatic differentiation (the tests' oracle for the
  /// tangent derived by hand); it always fills the tangent.
  bool wall_contact_spring_by_ad(double radius, const ContactSettings &s, double weight,
                                 double stiffness_ratio, const core::Vec2 &x, const core::Vec2 &x_old,
                                 double dt, const contact::FrictionHistory &old, ContactContribution &out,
                                 SpringFriction &friction, double friction_scale = 1.0);

  /// The friction alone of point x[0] against the segment x[1]-x[2] (the
  /// closest point q, clamped to the ends; normal force k w (d - |x0 - q|))
  /// by the discrete model's law, as wall_contact_spring: a tangential
  /// spring of stiffness ratio * k w, elongated by the slip of the step
  /// tau . ((x0 - x0_old) - ((1 - t)(x1 - x1_old) + t (x2 - x2_old))),
  /// tau the contact tangent at x, capped at mu_st F_n while sticking and
  /// mu_d F_n while sliding. out holds only friction: its residual equals
  /// its friction residual, and its tangent is friction_scale times the
  /// residual's derivative (left zero when out.want_tangent is false).
  /// Returns false when the point does not touch.
  bool point_segment_spring_friction(const ContactSettings &s, double weight, double stiffness_ratio,
                                     const std::array<core::Vec2, 3> &x,
                                     const std::array<core::Vec2, 3> &x_old, double dt,
                                     const contact::FrictionHistory &old, ContactContribution &out,
                                     SpringFriction &friction, double friction_scale = 1.0);
  /// The same by automatic differentiation (the tests' oracle for the
  /// tangent derived by hand); it always fills the tangent.
  bool point_segment_spring_friction_by_ad(const ContactSettings &s, double weight, double stiffness_ratio,
                                           const std::array<core::Vec2, 3> &x,
                                           const std::array<core::Vec2, 3> &x_old, double dt,
                                           const contact::FrictionHistory &old, ContactContribution &out,
                                           SpringFriction &friction, double friction_scale = 1.0);

  /// Point x[0] against the segment x[1]-x[2] (the closest point of the
  /// segment, clamped to its ends). t: the segment parameter of the closest
  /// point. Returns false when they are farther apart than d (or touch at
  /// zero distance). Residual and tangent cover the 6 coordinates.
  bool point_segment_contact(const ContactSettings &s, double weight, const std::array<core::Vec2, 3> &x,
                             const std::array<core::Vec2, 3> &v0, double c, ContactContribution &out,
                             double &t, double friction_scale = 1.0);

  /// point_segment_contact with its tangent by automatic differentiation
  /// (Sacado): the oracle of the hand-derived tangent in tests.
  bool point_segment_contact_by_ad(const ContactSettings &s, double weight,
                                   const std::array<core::Vec2, 3> &x, const std::array<core::Vec2, 3> &v0,
                                   double c, ContactContribution &out, double &t,
                                   double friction_scale = 1.0);

  /// Point x[0] against point x[1]: the penalty and friction of
  /// point_segment_contact for a segment shrunk to the point x[1]. Returns
  /// false when they are d or
  /// more apart (or coincide). Residual and tangent cover the 4 coordinates.
  bool point_point_contact(const ContactSettings &s, double weight, const std::array<core::Vec2, 2> &x,
                           const std::array<core::Vec2, 2> &v0, double c, ContactContribution &out,
                           double friction_scale = 1.0);

  /// Self contact of a point with a stretch of wire, the share of one
  /// segment: point x[0] against the segment x[1]-x[2] (point_segment_contact)
  /// less, when `next_presses` (the segment after it, from x[2] on, may press
  /// the point too), the contact of x[0] with the shared node x[2] alone
  /// (point_point_contact). Summed over the segments of a stretch, a point
  /// facing its straight part or its outer side feels exactly its contact
  /// with the nearest point of the stretch, and the sum is continuously
  /// differentiable wherever the point is: in the crease on the inner side
  /// of a bend both segments press it, less what the node alone would (a
  /// rule that keeps only the nearest segment turns the force by the bend's
  /// angle across the crease). t: the segment parameter of the closest
  /// point; vertex_force: the normal force of the node term taken away (0
  /// when none). out.normal_force and out.overlap are the segment's own.
  /// Returns false when the point does not touch the segment.
  bool point_stretch_contact(const ContactSettings &s, double weight, const std::array<core::Vec2, 3> &x,
                             const std::array<core::Vec2, 3> &v0, double c, bool next_presses,
                             ContactContribution &out, double &t, double &vertex_force,
                             double friction_scale = 1.0);

  /// Segment a0-a1 against segment b0-b1 (points 0..3 in that order). In the
  /// plane the closest points of two segments that do not cross always
  /// involve an end point; the case is chosen from the current positions.
  /// Returns false when they are farther apart than d (or cross).
  bool segment_contact(const ContactSettings &s, double weight, const std::array<core::Vec2, 4> &x,
                       const std::array<core::Vec2, 4> &v0, double c, ContactContribution &out,
                       double friction_scale = 1.0);
  /// The walls of a channel acting on one rod element (Lagrange, nodes at
  /// node_position in [0, 1], rest length h): energy (k/2) times the integral
  /// of y^2 over the part of the element with s < 0, s the distance past the
  /// mouth along `axis` and y the offset along `across`: the channel's axis
  /// and its normal for the paper's channels, the normal of the mouth's
  /// chord (between its corners) and the axis' normal for channels anywhere.
  /// X holds the node positions relative to the mouth (x0, y0, x1, y1, ...),
  /// a point of the channel's axis on the cut. The cut of an
  /// element crossing the mouth is found by bisection, and the gradient
  /// carries the moving end's term. With `tangent` (2n x 2n, row major) also
  /// the derivative of the gradient: exact for an element wholly inside,
  /// central differences of the gradient (step 1e-6, positions in d) for one
  /// crossing the mouth. Returns false when the element lies wholly outside
  /// (s >= 0 at both ends).
  bool channel_wall_element(const std::vector<double> &node_position, double h, double k, const double *X,
                            const core::Vec2 &axis, const core::Vec2 &across, double &energy,
                            double *gradient, double *tangent = nullptr);

} // namespace wirefem::fem
