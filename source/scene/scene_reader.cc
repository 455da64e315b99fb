#include <wirefem/scene/scene_reader.h>

#include <fmt/format.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

namespace wirefem::scene
{
  namespace
  {
    using dealii::ParameterHandler;
    namespace Patterns = dealii::Patterns;

    std::string trim(const std::string &s)
    {
      const auto b = s.find_first_not_of(" \t\r\n");
      if (b == std::string::npos)
        return "";
      const auto e = s.find_last_not_of(" \t\r\n");
      return s.substr(b, e - b + 1);
    }

    std::vector<std::string> split_path(const std::string &key)
    {
      std::vector<std::string> parts;
      std::stringstream ss(key);
      std::string part;
      while (std::getline(ss, part, '/'))
        parts.push_back(trim(part));
      return parts;
    }

    // ParameterHandler only Asserts (debug builds) on undeclared keys, so the
    // reader keeps its own table of declared keys and their patterns: every
    // value is checked here before it reaches the handler.
    class Declarations
    {
    public:
      explicit Declarations(ParameterHandler &prm)
        : prm(prm)
      {
      }

      void declare(const std::string &path, const std::string &default_value,
                   const Patterns::PatternBase &pattern, const std::string &doc)
      {
        auto parts = split_path(path);
        const std::string name = parts.back();
        parts.pop_back();
        for (const auto &s : parts)
          prm.enter_subsection(s);
        prm.declare_entry(name, default_value, pattern, doc);
        for (std::size_t i = 0; i < parts.size(); ++i)
          prm.leave_subsection();
        table[canonical(path)] = {path, pattern.clone()};
      }

      /// Sets `key` to `value`; `where` names the file (and line) for errors.
      void set(const std::string &where, const std::string &key, const std::string &value)
      {
        const auto it = table.find(canonical(key));
        if (it == table.end())
          throw InputError(where + ": " + key + ": no such key (see --print-parameters)");
        if (!it->second.pattern->match(value))
          throw InputError(where + ": " + it->second.path + ": '" + value +
                           "' is not a valid value; expected " +
                           it->second.pattern->description(Patterns::PatternBase::Text));
        auto parts = split_path(it->second.path);
        const std::string name = parts.back();
        parts.pop_back();
        for (const auto &s : parts)
          prm.enter_subsection(s);
        prm.set(name, value);
        for (std::size_t i = 0; i < parts.size(); ++i)
          prm.leave_subsection();
      }

      std::string get(const std::string &path) const
      {
        auto parts = split_path(path);
        const std::string name = parts.back();
        parts.pop_back();
        for (const auto &s : parts)
          prm.enter_subsection(s);
        const std::string value = prm.get(name);
        for (std::size_t i = 0; i < parts.size(); ++i)
          prm.leave_subsection();
        return value;
      }

      double get_double(const std::string &path) const { return std::stod(get(path)); }
      bool get_bool(const std::string &path) const
      {
        const std::string v = get(path);
        return v == "true" || v == "yes" || v == "1";
      }

      /// Every entry outside Output as "Section/Key = value" lines, sorted
      /// by key; numbers written in one canonical form, so that 25 and 25.0
      /// read alike.
      std::string fingerprint() const
      {
        std::string out;
        for (const auto &[key, entry] : table)
          {
            if (key.rfind("output/", 0) == 0)
              continue;
            std::string value = get(entry.path);
            try
              {
                std::size_t used = 0;
                const double x = std::stod(value, &used);
                if (used == value.size())
                  value = fmt::format("{}", x);
              }
            catch (const std::exception &)
              {
              }
            out += entry.path + " = " + value + "\n";
          }
        return out;
      }

    private:
      // Keys match regardless of spacing around '/' and of case, so that
      // "contact/friction/static coefficient" is accepted on the command line.
      static std::string canonical(const std::string &key)
      {
        std::string out;
        for (const auto &p : split_path(key))
          {
            if (!out.empty())
              out += '/';
            for (const char c : p)
              out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
          }
        return out;
      }

      struct Entry
      {
        std::string path;
        std::unique_ptr<Patterns::PatternBase> pattern;
      };
      ParameterHandler &prm;
      std::map<std::string, Entry> table;
    };

    void declare_all(Declarations &d)
    {
      const auto any_double = Patterns::Double();
      const auto positive = Patterns::Double(0.0);
      const auto boolean = Patterns::Bool();

      d.declare("Model", "discrete", Patterns::Selection("discrete|fem"),
                "Wire model: 'discrete' (the paper's spring chain) or 'fem' (geometrically exact rod).");
      d.declare("Set-up", "injection", Patterns::Selection("injection|cantilever|capstan"),
                "'injection': the wire pushed into the cavity (the paper). 'cantilever': a benchmark of "
                "validation/, a straight rod clamped at the origin and loaded at its free end "
                "(Cantilever subsection). 'capstan': a benchmark of validation/, a wire on the cavity "
                "wall pushed along it against an end force (Capstan subsection; the FEM under velocity "
                "control only).");
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
      d.declare("Cavity/Radius", "10", any_double,
                "Cavity radius r in units of the wire diameter d, i.e. f = r/d. Must be > 1.");

      d.declare("Wire/Axial stiffness", "1000", any_double,
                "EA (force). The discrete model uses k1 = EA/lambda_0.");
      d.declare("Wire/Bending stiffness", "60", any_double,
                "EI (force d^2). The discrete model uses k2 = EI/lambda_0.");
      d.declare("Wire/Mass per length", "1", any_double, "rho A (mass per unit length d).");
      d.declare("Wire/Plasticity/Enabled", "true", boolean,
                "Elastoplastic bending. The wire is elastic anyway when Yield curvature * lambda_0 >= pi.");
      d.declare("Wire/Plasticity/Yield curvature", "0.04", any_double,
                "kappa_theta (1/d): yield moment EI*kappa_theta; alpha_theta = kappa_theta*lambda_0. "
                "Paper: 0 ... 0.06; pi/lambda_0 is elastic.");
      d.declare("Wire/Plasticity/Hardening slope", "0.05", any_double,
                "s in [0, 1]: post-yield slope s*EI of the moment-curvature law; unloading with slope EI.");
      d.declare("Wire/Plasticity/Hardening", "kinematic", Patterns::Selection("kinematic|isotropic"),
                "Linear kinematic (default: the yield range of width 2 M_y translates) or linear "
                "isotropic (the yield range grows). The paper does not say which.");

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
      d.declare("Injection/Maximum time", "inf", Patterns::Anything(),
                "Stop at this time ('inf': no limit).");

      d.declare("Discrete/Segment length", "1", any_double, "lambda_0 (d): rest length of a spring.");
      d.declare("Discrete/Time step", "0", any_double,
                "Explicit time step. 0: Time step factor * the stability limit of the stiffest term.");
      d.declare("Discrete/Time step factor", "0.25", any_double,
                "Fraction of the estimated stability limit 2/omega_max used when Time step = 0.");
      d.declare("Discrete/Translational damping", "0", any_double,
                "gamma (1/time): viscous force -gamma m v on every free node against the fixed frame. "
                "Off by default: it drags wire sliding along itself with a distributed axial load "
                "gamma rho A v that folds spans longer than (4 pi^2 EI/(gamma rho A v))^(1/3) near the "
                "inlets (36 d at gamma = 0.05, v = 1) - no such drag exists in the experiment. The "
                "internal axial and rotational dashpots damp the wire instead.");
      d.declare("Discrete/Rotational damping", "0.5", any_double,
                "c (force d time): viscous moment -c dzeta/dt at each rotational spring; damps the "
                "highest bending modes (period ~0.2) and leaves slow loop motion alone.");

      d.declare("Discrete/Axial damping", "3", any_double,
                "c_a (force time / d): dashpot parallel to each tensile spring, tension c_a dlambda/dt. "
                "Damps axial waves (about 10% of critical for the shortest one at the paper's values, "
                "c_a = 0.1 sqrt(k1 m)) that otherwise dominate the measured inlet force; no drag on "
                "rigid motion.");
      d.declare("FEM/Formulation", "reissner", Patterns::Selection("reissner|kirchhoff"),
                "Rod theory: 'reissner' (shear-deformable, shear stiffness GA) or 'kirchhoff' (shear-rigid: "
                "the shear strain is held at zero by a penalty Kirchhoff penalty * EA).");
      d.declare("FEM/Degree", "1", Patterns::Integer(1, 3),
                "Polynomial degree p of x, y and theta on each element (1, 2 or 3). The stiffness is "
                "integrated with p Gauss points (reduced), which keeps thin rods free of locking.");
      d.declare("FEM/Element length", "1", any_double,
                "Rest length h (d) of an element. The dashpots of the discrete model carry over as "
                "eta_a = Discrete/Axial damping * lambda_0 and eta_b = Discrete/Rotational damping * "
                "lambda_0 (its continuum limit, like EA = k1 lambda_0).");
      d.declare("FEM/Shear stiffness", "-1", any_double,
                "GA (force) of the Reissner rod. Negative: 0.9 EA/(2 (1 + 0.3)), a round wire with "
                "Poisson ratio 0.3 and shear coefficient 0.9.");
      d.declare("FEM/Kirchhoff penalty", "1000", any_double,
                "Kirchhoff formulation: shear penalty as a multiple of EA.");
      d.declare("FEM/Integrator", "generalized-alpha",
                Patterns::Selection("generalized-alpha|quasi-static|explicit"),
                "'generalized-alpha': implicit dynamics, Newton with line search and adaptive step; "
                "'quasi-static': no inertia (equilibrium of elastic, viscous and contact forces); "
                "'explicit': central differences with a lumped mass matrix (for comparison).");
      d.declare("FEM/Spectral radius", "0.9", any_double,
                "rho_infinity in [0, 1] of generalized-alpha: 1 keeps every frequency (no numerical "
                "dissipation), smaller values damp the unresolved high frequencies.");
      d.declare("FEM/Time step", "0", any_double,
                "Implicit: the first and largest time step; the step halves when Newton fails and "
                "grows again when it converges easily. 0: 0.025 d / Injection/Speed, at most 0.025 "
                "(smaller steps need fewer Newton iterations: on prm/quick.prm 0.025 is both cheaper and "
                "more accurate than 0.05). "
                "Explicit: the step; 0: 0.5 of the estimated stability limit.");
      d.declare("FEM/Minimum time step", "1e-7", any_double,
                "Below this the implicit step is not cut further: the run stops with a message.");
      d.declare("FEM/Newton tolerance", "1e-8", any_double,
                "Newton converges when the residual norm is below this times the force scale "
                "(EA + the largest inertial force) or the update below it times d.");
      d.declare("FEM/Friction law", "regularised", Patterns::Selection("regularised|spring"),
                "regularised: mu(v) tanh(v/v_th), smooth, creeps below v_th (the injection scenes). "
                "spring: the discrete model's law (a tangential spring capped at mu_st F_n while "
                "sticking, mu_d F_n while sliding), with a sharp slip onset; Set-up = capstan only.");
      d.declare("FEM/Maximum iterations", "15", Patterns::Integer(2, 200),
                "Newton iterations before the step is cut.");
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
      d.declare("Debug/Keep neutral effects", "false", boolean,
                "Build friction and plasticity even when their parameters are neutral "
                "(mu = 0, kappa_theta*lambda_0 >= pi); for checking that they change nothing.");
    }

    double parse_double_or_inf(const std::string &s)
    {
      return s == "inf" ? INFINITY : std::stod(s);
    }

    void check(bool ok, const std::string &where, const std::string &key, const std::string &why)
    {
      if (!ok)
        throw InputError(where + ": " + key + ": " + why);
    }

    Scene extract(const Declarations &d, const std::string &where)
    {
      Scene s;
      s.model = d.get("Model") == "fem" ? ModelType::fem : ModelType::discrete;
      const std::string setup = d.get("Set-up");
      s.setup = setup == "cantilever" ? Setup::cantilever
                : setup == "capstan"  ? Setup::capstan
                                      : Setup::injection;
      auto &cs = s.capstan;
      cs.wrap_angle = d.get_double("Capstan/Wrap angle");
      cs.end_force = d.get_double("Capstan/End force");
      cs.velocity_control = d.get("Capstan/Control") == "velocity";
      cs.speed = d.get_double("Capstan/Speed");
      cs.ramp_time = d.get_double("Capstan/Ramp time");
      cs.slide = d.get_double("Capstan/Slide");
      cs.force_rate = d.get_double("Capstan/Force rate");
      cs.slip_distance = d.get_double("Capstan/Slip distance");
      cs.trailing_roller = d.get("Capstan/Trailing end") == "roller";
      cs.maximum_time = d.get_double("Capstan/Maximum time");
      auto &cl = s.cantilever;
      cl.length = d.get_double("Cantilever/Length");
      cl.end_force_x = d.get_double("Cantilever/End force x");
      cl.end_force_y = d.get_double("Cantilever/End force y");
      cl.end_moment = d.get_double("Cantilever/End moment");
      cl.load_time = d.get_double("Cantilever/Load time");
      cl.load_history.clear();
      for (const auto &item : dealii::Utilities::split_string_list(d.get("Cantilever/Load history")))
        cl.load_history.push_back(std::stod(item));
      cl.points_per_leg = static_cast<unsigned int>(std::stoul(d.get("Cantilever/Points per leg")));
      cl.damping = d.get_double("Cantilever/Damping");
      cl.tolerance = d.get_double("Cantilever/Tolerance");
      cl.maximum_time = d.get_double("Cantilever/Maximum time");
      s.cavity.radius = d.get_double("Cavity/Radius");
      s.wire.axial_stiffness = d.get_double("Wire/Axial stiffness");
      s.wire.bending_stiffness = d.get_double("Wire/Bending stiffness");
      s.wire.mass_per_length = d.get_double("Wire/Mass per length");
      auto &pl = s.wire.plasticity;
      pl.enabled = d.get_bool("Wire/Plasticity/Enabled");
      pl.yield_curvature = d.get_double("Wire/Plasticity/Yield curvature");
      pl.hardening_slope = d.get_double("Wire/Plasticity/Hardening slope");
      pl.hardening =
          d.get("Wire/Plasticity/Hardening") == "isotropic" ? Hardening::isotropic : Hardening::kinematic;
      auto &c = s.contact;
      c.wall_contact = d.get_bool("Contact/Wall contact");
      c.self_contact = d.get_bool("Contact/Self contact");
      c.normal_stiffness = d.get_double("Contact/Normal stiffness");
      c.skin = d.get_double("Contact/Skin");
      c.exclusion_length = d.get_double("Contact/Exclusion length");
      auto &f = c.friction;
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
      auto &in = s.injection;
      in.speed = d.get_double("Injection/Speed");
      in.ramp_time = d.get_double("Injection/Ramp time");
      in.slow_start_length = d.get_double("Injection/Slow start length");
      in.slow_start_speed = d.get_double("Injection/Slow start speed");
      in.seed = static_cast<unsigned int>(std::stoul(d.get("Injection/Seed")));
      in.perturbation = d.get_double("Injection/Perturbation");
      in.mirror_asymmetry = d.get_double("Injection/Mirror asymmetry");
      in.tangential_channels = d.get("Injection/Channels") == "tangential";
      in.maximum_packing_density = d.get_double("Injection/Maximum packing density");
      in.jamming_force = d.get_double("Injection/Jamming force");
      in.jamming_window = d.get_double("Injection/Jamming window");
      try
        {
          in.maximum_time = parse_double_or_inf(d.get("Injection/Maximum time"));
        }
      catch (const std::exception &)
        {
          check(false, where, "Injection/Maximum time",
                "'" + d.get("Injection/Maximum time") + "' is not a number or 'inf'");
        }
      auto &ds = s.discrete;
      ds.segment_length = d.get_double("Discrete/Segment length");
      ds.time_step = d.get_double("Discrete/Time step");
      ds.time_step_factor = d.get_double("Discrete/Time step factor");
      ds.translational_damping = d.get_double("Discrete/Translational damping");
      ds.rotational_damping = d.get_double("Discrete/Rotational damping");
      ds.axial_damping = d.get_double("Discrete/Axial damping");
      auto &fe = s.fem;
      fe.formulation =
          d.get("FEM/Formulation") == "kirchhoff" ? Formulation::kirchhoff : Formulation::reissner;
      fe.degree = static_cast<unsigned int>(std::stoul(d.get("FEM/Degree")));
      fe.element_length = d.get_double("FEM/Element length");
      fe.shear_stiffness = d.get_double("FEM/Shear stiffness");
      if (fe.shear_stiffness < 0)
        fe.shear_stiffness = 0.9 * s.wire.axial_stiffness / 2.6;
      fe.kirchhoff_penalty = d.get_double("FEM/Kirchhoff penalty");
      const auto integrator = d.get("FEM/Integrator");
      fe.integrator = integrator == "explicit"       ? Integrator::explicit_lumped
                      : integrator == "quasi-static" ? Integrator::quasi_static
                                                     : Integrator::generalized_alpha;
      fe.spectral_radius = d.get_double("FEM/Spectral radius");
      fe.time_step = d.get_double("FEM/Time step");
      fe.minimum_time_step = d.get_double("FEM/Minimum time step");
      fe.newton_tolerance = d.get_double("FEM/Newton tolerance");
      fe.maximum_iterations = static_cast<unsigned int>(std::stoul(d.get("FEM/Maximum iterations")));
      fe.spring_friction = d.get("FEM/Friction law") == "spring";
      auto &o = s.output;
      o.directory = d.get("Output/Directory");
      o.interval = d.get_double("Output/Interval");
      o.vtu_interval = d.get_double("Output/VTU interval");
      o.picture_size = std::stoi(d.get("Output/Picture size"));
      o.progress = d.get("Output/Progress");
      o.checkpoint_interval = d.get_double("Output/Checkpoint interval");
      s.keep_neutral_effects = d.get_bool("Debug/Keep neutral effects");
      return s;
    }

    // Values that each pass their pattern but make no physical sense, alone
    // or together.
    void validate(const Scene &s, const std::string &w)
    {
      check(s.cavity.radius > 1.0, w, "Cavity/Radius", "must be larger than 1 (the wire diameter)");
      check(s.wire.axial_stiffness > 0, w, "Wire/Axial stiffness", "must be positive");
      check(s.wire.bending_stiffness >= 0, w, "Wire/Bending stiffness", "must not be negative");
      check(s.wire.mass_per_length > 0, w, "Wire/Mass per length", "must be positive");
      const auto &pl = s.wire.plasticity;
      check(pl.yield_curvature >= 0, w, "Wire/Plasticity/Yield curvature", "must not be negative");
      check(pl.hardening_slope >= 0 && pl.hardening_slope <= 1, w, "Wire/Plasticity/Hardening slope",
            "must be in [0, 1]");
      const auto &c = s.contact;
      check(c.normal_stiffness > 0, w, "Contact/Normal stiffness", "must be positive");
      check(c.skin > 0, w, "Contact/Skin", "must be positive");
      check(c.exclusion_length >= 0, w, "Contact/Exclusion length", "must not be negative");
      const auto &f = c.friction;
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
      const auto &in = s.injection;
      check(in.speed > 0, w, "Injection/Speed", "must be positive");
      check(in.ramp_time >= 0, w, "Injection/Ramp time", "must not be negative");
      check(in.slow_start_length >= 0, w, "Injection/Slow start length", "must not be negative");
      if (in.slow_start_length > 0)
        {
          check(in.slow_start_speed > 0, w, "Injection/Slow start speed", "must be positive");
          check(in.slow_start_length >= 0.5 * in.slow_start_speed * in.ramp_time, w,
                "Injection/Slow start length",
                "must be at least what the ramp injects, Slow start speed * Ramp time / 2");
        }
      check(in.perturbation >= 0, w, "Injection/Perturbation", "must not be negative");
      check(in.mirror_asymmetry >= 0, w, "Injection/Mirror asymmetry", "must not be negative");
      // The initial wire: straight across (2 r), or the S between tangential
      // inlets (pi (r - d/2)).
      const double l0 = in.tangential_channels ? M_PI * (s.cavity.radius - 0.5) : 2.0 * s.cavity.radius;
      const double phi0 = l0 / (M_PI * s.cavity.radius * s.cavity.radius);
      check(in.maximum_packing_density > phi0, w, "Injection/Maximum packing density",
            "must exceed the initial packing density " + std::to_string(phi0));
      check(in.maximum_packing_density <= 1.0, w, "Injection/Maximum packing density", "must not exceed 1");
      check(in.jamming_force > 0, w, "Injection/Jamming force", "must be positive");
      check(in.jamming_window > 0, w, "Injection/Jamming window", "must be positive");
      check(in.maximum_time > 0, w, "Injection/Maximum time", "must be positive");
      const auto &ds = s.discrete;
      if (s.setup == Setup::cantilever)
        {
          const auto &cl = s.cantilever;
          check(cl.length > 0, w, "Cantilever/Length", "must be positive");
          if (s.model == ModelType::discrete)
            {
              check(ds.segment_length > 0 && ds.segment_length <= 0.5 * cl.length, w,
                    "Discrete/Segment length", "must be in (0, L/2]");
              const double n = cl.length / ds.segment_length;
              check(std::abs(n - std::round(n)) < 1e-9 * n, w, "Discrete/Segment length",
                    "L / lambda_0 = " + std::to_string(n) + " must be a whole number of segments");
            }
          else
            {
              const double ne = cl.length / s.fem.element_length;
              check(s.fem.element_length > 0 && std::abs(ne - std::round(ne)) < 1e-9 * ne && ne >= 1, w,
                    "FEM/Element length",
                    "L / h = " + std::to_string(ne) + " must be a whole number of elements");
            }
          check(cl.load_time >= 0, w, "Cantilever/Load time", "must not be negative");
          check(cl.damping >= 0, w, "Cantilever/Damping", "must not be negative");
          check(cl.tolerance > 0, w, "Cantilever/Tolerance", "must be positive");
          check(cl.maximum_time > cl.load_time, w, "Cantilever/Maximum time", "must exceed the load time");
        }
      else if (s.setup == Setup::capstan)
        {
          const auto &cs = s.capstan;
          check(s.model == ModelType::discrete || cs.velocity_control || s.fem.spring_friction, w,
                "Capstan/Control",
                "'force' with Model = fem needs FEM/Friction law = spring (the regularised law creeps below "
                "the threshold velocity: it has no sharp slip onset to measure)");
          check(!s.plastic_bending(), w, "Wire/Plasticity/Enabled",
                "Set-up = capstan bends the wire elastically to the wall: set it false");
          check(cs.wrap_angle > 0 && cs.wrap_angle <= 2.8, w, "Capstan/Wrap angle",
                "must be in (0, 2.8] (the wire must stay clear of the channel openings)");
          check(cs.end_force > 0, w, "Capstan/End force", "must be positive");
          check(cs.speed > 0, w, "Capstan/Speed", "must be positive");
          check(cs.ramp_time >= 0, w, "Capstan/Ramp time", "must not be negative");
          check(cs.slide >= cs.speed * cs.ramp_time, w, "Capstan/Slide",
                "must be at least Speed * Ramp time (the push force is averaged over the second half of the "
                "sliding at full speed)");
          check(cs.force_rate > 0, w, "Capstan/Force rate", "must be positive");
          check(cs.slip_distance > 0, w, "Capstan/Slip distance", "must be positive");
          check(cs.maximum_time > 0, w, "Capstan/Maximum time", "must be positive");
          check(ds.segment_length > 0 && ds.segment_length <= 0.25 * s.cavity.radius, w,
                "Discrete/Segment length", "must be in (0, r/4]");
        }
      else
        {
          check(ds.segment_length > 0 && ds.segment_length <= 0.25 * s.cavity.radius, w,
                "Discrete/Segment length", "must be in (0, r/4]");
          const double n_segments = 2.0 * s.cavity.radius / ds.segment_length;
          check(std::abs(n_segments - std::round(n_segments)) < 1e-9 * n_segments, w,
                "Discrete/Segment length",
                "2 r / lambda_0 = " + std::to_string(n_segments) + " must be a whole number of segments");
        }
      check(ds.time_step >= 0, w, "Discrete/Time step", "must not be negative");
      check(ds.time_step_factor > 0 && ds.time_step_factor < 1, w, "Discrete/Time step factor",
            "must be in (0, 1)");
      check(ds.translational_damping >= 0, w, "Discrete/Translational damping", "must not be negative");
      check(ds.axial_damping >= 0, w, "Discrete/Axial damping", "must not be negative");
      check(ds.rotational_damping >= 0, w, "Discrete/Rotational damping", "must not be negative");
      const auto &fe = s.fem;
      if (s.setup == Setup::injection)
        check(fe.element_length > 0 && fe.element_length <= 0.25 * s.cavity.radius, w, "FEM/Element length",
              "must be in (0, r/4]");
      check(fe.shear_stiffness > 0, w, "FEM/Shear stiffness", "must be positive");
      check(fe.kirchhoff_penalty > 0, w, "FEM/Kirchhoff penalty", "must be positive");
      check(fe.spectral_radius >= 0 && fe.spectral_radius <= 1, w, "FEM/Spectral radius",
            "must be in [0, 1]");
      check(fe.time_step >= 0, w, "FEM/Time step", "must not be negative");
      check(fe.minimum_time_step > 0, w, "FEM/Minimum time step", "must be positive");
      check(fe.newton_tolerance > 0, w, "FEM/Newton tolerance", "must be positive");
      check(!s.contact.friction.surface_torque || s.model == ModelType::discrete, w,
            "Contact/Friction/Surface torque", "is implemented for Model = discrete only");
      check(!fe.spring_friction || s.model == ModelType::discrete || s.setup == Setup::capstan, w,
            "FEM/Friction law", "'spring' is implemented for Set-up = capstan only");
      check(s.output.interval > 0, w, "Output/Interval", "must be positive");
      check(s.output.checkpoint_interval >= 0, w, "Output/Checkpoint interval", "must not be negative");
      check(s.output.vtu_interval >= 0, w, "Output/VTU interval", "must not be negative");
    }

    // A line-by-line reader of the prm format (subsection/end/set, '#'
    // comments, '\' continuation) so that errors carry the file and line.
    void read_prm_file(Declarations &d, const std::string &file)
    {
      if (!std::filesystem::is_regular_file(file))
        throw InputError(file + ": cannot open the scene file (no such file)");
      std::ifstream in(file);
      if (!in)
        throw InputError(file + ": cannot open the scene file");
      std::vector<std::string> path;
      std::string raw, line;
      int line_no = 0, start_line = 0;
      while (std::getline(in, raw))
        {
          ++line_no;
          if (line.empty())
            start_line = line_no;
          const auto hash = raw.find('#');
          std::string part = trim(hash == std::string::npos ? raw : raw.substr(0, hash));
          if (!part.empty() && part.back() == '\\')
            {
              line += part.substr(0, part.size() - 1) + " ";
              continue;
            }
          line += part;
          const std::string where = file + ":" + std::to_string(start_line);
          const std::string l = trim(line);
          line.clear();
          if (l.empty())
            continue;
          if (l.rfind("subsection ", 0) == 0)
            path.push_back(trim(l.substr(11)));
          else if (l == "end")
            {
              if (path.empty())
                throw InputError(where + ": 'end' without a matching subsection");
              path.pop_back();
            }
          else if (l.rfind("set ", 0) == 0)
            {
              const auto eq = l.find('=');
              if (eq == std::string::npos)
                throw InputError(where + ": '" + l + "': expected 'set Key = value'");
              std::string key;
              for (const auto &p : path)
                key += p + "/";
              key += trim(l.substr(4, eq - 4));
              d.set(where, key, trim(l.substr(eq + 1)));
            }
          else
            throw InputError(where + ": '" + l + "': expected 'subsection', 'set' or 'end'");
        }
      if (!path.empty())
        throw InputError(file + ": subsection '" + path.back() + "' is not closed with 'end'");
    }
  } // namespace

  Scene read_scene(const std::string &prm_file, const std::vector<std::string> &overrides)
  {
    ParameterHandler prm;
    Declarations d(prm);
    declare_all(d);
    if (!prm_file.empty())
      read_prm_file(d, prm_file);
    const std::string file_label = prm_file.empty() ? std::string("(no scene file)") : prm_file;
    for (const auto &o : overrides)
      {
        const auto eq = o.find('=');
        if (eq == std::string::npos)
          throw InputError(file_label + " (--set): '" + o + "': expected \"Section/Key=value\"");
        d.set(file_label + " (--set)", trim(o.substr(0, eq)), trim(o.substr(eq + 1)));
      }
    Scene s = extract(d, file_label);
    s.fingerprint = d.fingerprint();
    s.prm_file = prm_file;
    s.name = prm_file.empty() ? "default" : std::filesystem::path(prm_file).stem().string();
    validate(s, file_label);
    if (s.output.directory.empty())
      s.output.directory = "output/" + s.name;
    return s;
  }

  void print_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    Declarations d(prm);
    declare_all(d);
    prm.print_parameters(out, ParameterHandler::PRM | ParameterHandler::KeepDeclarationOrder);
  }
} // namespace wirefem::scene
