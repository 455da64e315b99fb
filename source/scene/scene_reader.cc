#include "declarations.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

namespace wirefem::scene
{
  namespace
  {
    /// Every key of a scene, bound to its member of `s`, in the order
    /// --print-parameters lists them: the top-level choices, then one
    /// section after another.
    void declare_all(Declarations &d, Scene &s)
    {
      d.choice<ModelType>(
          "Model", "discrete", {{"discrete", ModelType::discrete}, {"fem", ModelType::fem}},
          "Wire model: 'discrete' (the paper's spring chain) or 'fem' (geometrically exact rod).", s.model);
      d.choice<Setup>(
          "Set-up", "injection",
          {{"injection", Setup::injection}, {"cantilever", Setup::cantilever}, {"capstan", Setup::capstan}},
          "'injection': the wire pushed into the cavity (the paper). 'cantilever': a benchmark of "
          "validation/, a straight rod clamped at the origin and loaded at its free end "
          "(Cantilever subsection). 'capstan': a benchmark of validation/, a wire on the cavity "
          "wall pushed along it against an end force (Capstan subsection; the FEM under velocity "
          "control only).",
          s.setup);
      declare_sections(d, s);
      d.flag("Debug/Keep neutral effects", "false",
             "Build friction and plasticity even when their parameters are neutral "
             "(mu = 0, kappa_theta*lambda_0 >= pi); for checking that they change nothing.",
             s.keep_neutral_effects);
    }

    /// The discretisation must fit the set-up: whole segments or elements
    /// along the cantilever, whole segments across the cavity.
    void validate_discretisation(const Scene &s, const std::string &w)
    {
      const auto &ds = s.discrete;
      if (s.setup == Setup::cantilever)
        {
          const double L = s.cantilever.length;
          if (s.model == ModelType::discrete)
            {
              check(ds.segment_length > 0 && ds.segment_length <= 0.5 * L, w, "Discrete/Segment length",
                    "must be in (0, L/2]");
              const double n = L / ds.segment_length;
              check(std::abs(n - std::round(n)) < 1e-9 * n, w, "Discrete/Segment length",
                    "L / lambda_0 = " + std::to_string(n) + " must be a whole number of segments");
            }
          else
            {
              const double ne = L / s.fem.element_length;
              check(s.fem.element_length > 0 && std::abs(ne - std::round(ne)) < 1e-9 * ne && ne >= 1, w,
                    "FEM/Element length",
                    "L / h = " + std::to_string(ne) + " must be a whole number of elements");
            }
          return;
        }
      if (s.setup == Setup::capstan)
        {
          check(ds.segment_length > 0 && ds.segment_length <= 0.25 * s.cavity.radius, w,
                "Discrete/Segment length", "must be in (0, r/4]");
          return;
        }
      // Injection: the lengths' upper bound (r >= 4 x the element of the
      // model that runs) is validate_cavity_size's.
      check(ds.segment_length > 0, w, "Discrete/Segment length", "must be positive");
      const double n_segments = 2.0 * s.cavity.radius / ds.segment_length;
      check(std::abs(n_segments - std::round(n_segments)) < 1e-9 * n_segments, w, "Discrete/Segment length",
            "2 r / lambda_0 = " + std::to_string(n_segments) + " must be a whole number of segments");
      check(s.fem.element_length > 0, w, "FEM/Element length", "must be positive");
    }

    /// Values that each pass their section's checks but not together: what
    /// a set-up or a model does not implement.
    void validate_combinations(const Scene &s, const std::string &w)
    {
      if (s.setup == Setup::capstan)
        {
          check(s.model == ModelType::discrete || s.capstan.velocity_control || s.fem.spring_friction, w,
                "Capstan/Control",
                "'force' with Model = fem needs FEM/Friction law = spring (the regularised law creeps below "
                "the threshold velocity: it has no sharp slip onset to measure)");
          check(!s.plastic_bending(), w, "Wire/Plasticity/Enabled",
                "Set-up = capstan bends the wire elastically to the wall: set it false");
        }
      check(!s.contact.friction.surface_torque || s.model == ModelType::discrete, w,
            "Contact/Friction/Surface torque", "is implemented for Model = discrete only");
      check(
          !s.fem.modified_newton || s.fem.linear_solver == scene::LinearSolver::refactorise, w, "FEM/Newton",
          "'modified' reuses LU factors in direct solves: it needs FEM/Linear solver = refactorise or auto");
      check(s.fem.linear_tolerance < 1.0, w, "FEM/Linear tolerance",
            "must be below 1 (GMRES would stop before it starts; 0: chosen by FEM/Linear solver)");
      if (s.model == ModelType::fem && s.fem.spring_self_friction)
        {
          check(s.fem.integrator != Integrator::explicit_lumped, w, "FEM/Self friction law",
                "'spring' needs an implicit integrator (FEM/Integrator = generalized-alpha or quasi-static)");
          check(s.fem.contact_points == 0, w, "FEM/Self friction law",
                "'spring' acts at the nodes: it needs FEM/Contact points = 0");
        }
    }

    // Values that each pass their pattern but make no physical sense, alone
    // or together. The order is the order in which a user meets the keys.
    /// The injection set-up's cavity against its discretisation and this
    /// machine's memory, before anything is allocated: a cavity narrower
    /// than 4 segments (or elements) across, or a wire at the maximum
    /// packing density whose storage would not fit in memory, is refused
    /// with the radius named. Bytes per node measured on the shipped
    /// scenes (storage, neighbour lists, and for the FEM the tangent and
    /// its LU factors), doubled for safety.
    void validate_cavity_size(const Scene &s, const std::string &w)
    {
      if (s.setup != Setup::injection)
        return;
      const double r = s.cavity.radius;
      const bool fem = s.model == ModelType::fem;
      if (!(s.discrete.segment_length > 0.0) || !(s.fem.element_length > 0.0))
        return; // their own checks say so
      const double element =
          fem ? std::max(s.discrete.segment_length, s.fem.element_length) : s.discrete.segment_length;
      check(r >= 4.0 * element, w, "Cavity/Radius",
            fmt::format("r = {:g} is less than 4 x {} ({:g}): the wire across the cavity needs at least 8 "
                        "of them",
                        r,
                        fem && s.fem.element_length > s.discrete.segment_length ? "FEM/Element length"
                                                                                : "Discrete/Segment length",
                        element));
      const double phi = std::min(1.0, s.injection.maximum_packing_density);
      const double length = phi * M_PI * r * r; // d = 1
      const double nodes =
          fem ? length / s.fem.element_length * s.fem.degree : length / s.discrete.segment_length;
      const double bytes = nodes * (fem ? 8192.0 : 512.0);
      const double memory =
          static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
      check(
          !(bytes > memory) || memory <= 0, w, "Cavity/Radius",
          fmt::format("r = {:g} needs about {:.3g} GB ({:.2g} nodes up to Injection/Maximum packing density "
                      "{:g}), more than this machine's {:.3g} GB",
                      r, bytes / 1e9, nodes, phi, memory / 1e9));
    }

    void validate(const Scene &s, const Declarations &d, const std::string &w)
    {
      s.cavity.validate(w);
      validate_cavity_size(s, w);
      d.check_ranges("Wire/", w);
      d.check_ranges("Contact/", w);
      s.contact.validate(w);
      d.check_ranges("Injection/", w);
      s.injection.validate(w, s.cavity.radius);
      validate_wall(s, w);
      if (s.setup == Setup::cantilever)
        {
          d.check_ranges("Cantilever/", w);
          s.cantilever.validate(w);
        }
      validate_combinations(s, w);
      if (s.setup == Setup::capstan)
        {
          d.check_ranges("Capstan/", w);
          s.capstan.validate(w);
        }
      validate_discretisation(s, w);
      d.check_ranges("Discrete/", w);
      d.check_ranges("FEM/", w);
      d.check_ranges("Output/", w);
    }

    // A line-by-line reader of the prm format (subsection/end/set, '#'
    // comments, '\' continuation) so that errors carry the file and line.
    void read_prm_file(Declarations &d, const std::string &file)
    {
      if (std::filesystem::is_directory(file))
        throw InputError(file + ": is a directory, not a scene file");
      if (!std::filesystem::is_regular_file(file))
        throw InputError(file + ": cannot open the scene file (no such file)");
      std::ifstream in(file);
      if (!in)
        throw InputError(file + ": cannot open the scene file");
      std::vector<std::string> path;
      std::map<std::string, int> set_at; // key (lower case) -> line of its 'set'
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
              // A key set twice in one file: the second would win unseen.
              std::string folded;
              for (const char c : key)
                folded += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
              if (const auto [first, inserted] = set_at.emplace(folded, start_line); !inserted)
                throw InputError(where + ": " + key + ": set again (first set on line " +
                                 std::to_string(first->second) + ")");
              d.set(where, key, trim(l.substr(eq + 1)));
            }
          else
            throw InputError(where + ": '" + l + "': expected 'subsection', 'set' or 'end'");
        }
      if (!path.empty())
        throw InputError(file + ": subsection '" + path.back() + "' is not closed with 'end'");
    }

    /// Cavity/Vertex file: its 'x y' lines into the polygon's vertices, and
    /// its numbers into the fingerprint.
    void read_vertex_file(Scene &s, const std::string &scene_file, const std::string &where)
    {
      auto &c = s.cavity;
      if (c.shape != CavityShape::polygon || c.vertex_file.empty())
        return;
      std::filesystem::path path(c.vertex_file);
      if (path.is_relative() && !scene_file.empty())
        path = std::filesystem::path(scene_file).parent_path() / path;
      std::ifstream in(path);
      check(std::filesystem::is_regular_file(path) && in, where, "Cavity/Vertex file",
            "cannot open '" + path.string() + "'");
      c.vertices.clear();
      std::string line;
      for (int number = 1; std::getline(in, line); ++number)
        {
          line = trim(line.substr(0, line.find('#')));
          if (line.empty())
            continue;
          std::istringstream words(line);
          double x, y;
          std::string rest;
          check(static_cast<bool>(words >> x >> y) && !(words >> rest) && std::isfinite(x) &&
                    std::isfinite(y),
                where, "Cavity/Vertex file",
                fmt::format("{}:{}: '{}' is not two numbers 'x y'", path.string(), number, line));
          c.vertices.push_back(x);
          c.vertices.push_back(y);
        }
      s.fingerprint += fmt::format("\nCavity/Vertex file numbers = {}", fmt::join(c.vertices, ", "));
    }
  } // namespace

  Scene read_scene(const std::string &prm_file, const std::vector<std::string> &overrides)
  {
    ParameterHandler prm;
    Declarations d(prm);
    Scene s;
    declare_all(d, s);
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
    d.read_all(file_label);
    s.contact.resolve();
    s.fem.resolve(s.wire.axial_stiffness, s.discrete);
    s.fingerprint = d.fingerprint();
    s.prm_file = prm_file;
    s.name = prm_file.empty() ? "default" : std::filesystem::path(prm_file).stem().string();
    read_vertex_file(s, prm_file, file_label);
    validate(s, d, file_label);
    if (s.output.directory.empty())
      s.output.directory = "output/" + s.name;
    return s;
  }

  void print_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    Declarations d(prm);
    Scene unused;
    declare_all(d, unused);
    prm.print_parameters(out, ParameterHandler::PRM | ParameterHandler::KeepDeclarationOrder);
  }
} // namespace wirefem::scene
