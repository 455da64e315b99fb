#include <wirefem/analysis/observables.h>
#include <wirefem/analysis/shape_io.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace wirefem::analysis
{
  using core::Vec2;
  namespace fs = std::filesystem;

  namespace
  {
    [[noreturn]] void fail(const std::string &where, const std::string &reason)
    {
      throw ShapeError(where + ": " + reason);
    }

    std::string read_file(const std::string &file)
    {
      std::ifstream in(file);
      if (!in)
        fail(file, "cannot open");
      std::stringstream buffer;
      buffer << in.rdbuf();
      return buffer.str();
    }

    /// Arc length along the polyline and curvature from the turning angles.
    void complete_geometry(core::WireState &w)
    {
      const auto &p = w.points;
      const std::size_t n = p.size();
      if (w.arc_length.size() != n)
        {
          w.arc_length.assign(n, 0.0);
          for (std::size_t k = 1; k < n; ++k)
            w.arc_length[k] = w.arc_length[k - 1] + norm(p[k] - p[k - 1]);
        }
      if (w.curvature.size() != n)
        {
          w.curvature.assign(n, 0.0);
          for (std::size_t k = 1; k + 1 < n; ++k)
            {
              const Vec2 a = p[k] - p[k - 1], b = p[k + 1] - p[k];
              const double ds = 0.5 * (norm(a) + norm(b));
              if (ds > 0.0)
                w.curvature[k] = std::atan2(cross(a, b), dot(a, b)) / ds;
            }
        }
      for (auto *field : {&w.plastic_curvature, &w.bending_energy, &w.contact_force})
        field->resize(n, 0.0);
      w.injected_length = n > 1 ? w.arc_length.back() - w.arc_length.front() : 0.0;
    }

    void check_shape(const core::WireState &w, const std::string &file)
    {
      if (w.points.size() < 2)
        fail(file, "a wire needs at least two points");
      for (std::size_t k = 1; k < w.points.size(); ++k)
        if (norm(w.points[k] - w.points[k - 1]) == 0.0)
          fail(file, fmt::format("points {} and {} coincide", k - 1, k));
    }

    /// The numbers of `<DataArray ... Name="name" ...>` (or of the first
    /// DataArray after `<Points>` when name is empty) in an ASCII VTU file.
    std::vector<double> data_array(const std::string &text, const std::string &name, const std::string &file)
    {
      std::size_t at;
      if (name.empty())
        {
          at = text.find("<Points>");
          if (at != std::string::npos)
            at = text.find("<DataArray", at);
        }
      else
        at = text.find("Name=\"" + name + "\"");
      if (at == std::string::npos)
        fail(file, "no " + (name.empty() ? std::string("Points") : name) + " data");
      const auto open = text.find('>', at);
      const auto close = text.find("</DataArray>", open);
      if (open == std::string::npos || close == std::string::npos)
        fail(file, "malformed DataArray " + name);
      if (text.substr(at, open - at).find("format=\"ascii\"") == std::string::npos)
        fail(file, "only ASCII VTU files are read");
      std::istringstream in(text.substr(open + 1, close - open - 1));
      std::vector<double> values;
      double v;
      while (in >> v)
        values.push_back(v);
      return values;
    }
  } // namespace

  core::WireState read_shape_csv(const std::string &file, const ShapeOptions &options)
  {
    std::ifstream in(file);
    if (!in)
      fail(file, "cannot open");
    core::WireState w;
    double diameter = 1.0, radius = 0.0;
    const std::regex meta(R"(^\s*#\s*(diameter|radius)\s*=\s*([-+0-9.eE]+)\s*$)");
    std::string line;
    int line_no = 0;
    bool header_allowed = true;
    while (std::getline(in, line))
      {
        ++line_no;
        const std::string where = fmt::format("{}:{}", file, line_no);
        std::smatch m;
        if (std::regex_match(line, m, meta))
          {
            double value = 0.0;
            try
              {
                value = std::stod(m[2]);
              }
            catch (const std::exception &)
              {
                fail(where, std::string(m[1]) + ": '" + std::string(m[2]) + "' is not a number");
              }
            (m[1] == "diameter" ? diameter : radius) = value;
            continue;
          }
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#')
          continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream fields(line);
        double x, y;
        std::string rest;
        if (!(fields >> x >> y) || (fields >> rest))
          {
            if (header_allowed)
              {
                header_allowed = false;
                continue;
              }
            fail(where, "expected two numbers x,y");
          }
        if (!std::isfinite(x) || !std::isfinite(y))
          fail(where, "coordinates must be finite");
        header_allowed = false;
        w.points.push_back({x, y});
      }
    if (options.diameter)
      diameter = *options.diameter;
    if (options.cavity_radius)
      radius = *options.cavity_radius;
    if (!(diameter > 0.0))
      fail(file, "diameter: must be positive");
    if (radius < 0.0)
      fail(file, "radius: must not be negative");
    // Far beyond any cavity: the exact geometry of the loop count needs
    // coordinates whose squares stay finite.
    for (auto &p : w.points)
      {
        p = (1.0 / diameter) * p;
        if (!(std::abs(p.x) <= 1e9 && std::abs(p.y) <= 1e9))
          fail(file, fmt::format("a point lies {:g} diameters from the origin (at most 1e9)",
                                 std::max(std::abs(p.x), std::abs(p.y))));
      }
    w.cavity_radius = radius / diameter;
    check_shape(w, file);
    complete_geometry(w);
    return w;
  }

  core::WireState read_run_directory(const std::string &dir, const ShapeOptions &options)
  {
    const fs::path d(dir);
    const std::string pvd_file = (d / "wire.pvd").string();
    const std::string pvd = read_file(pvd_file);
    const auto last = pvd.rfind("file=\"");
    if (last == std::string::npos)
      fail(pvd_file, "lists no VTU file");
    const auto end = pvd.find('"', last + 6);
    const std::string vtu_file = (d / pvd.substr(last + 6, end - last - 6)).string();
    const std::string text = read_file(vtu_file);

    core::WireState w;
    const auto xyz = data_array(text, "", vtu_file);
    if (xyz.size() % 3 != 0)
      fail(vtu_file, "Points do not come in triples");
    for (std::size_t k = 0; k + 2 < xyz.size(); k += 3)
      w.points.push_back({xyz[k], xyz[k + 1]});
    w.arc_length = data_array(text, "arc_length", vtu_file);
    w.curvature = data_array(text, "curvature", vtu_file);
    if (w.arc_length.size() != w.points.size() || w.curvature.size() != w.points.size())
      fail(vtu_file, "point data do not match the points");
    check_shape(w, vtu_file);
    complete_geometry(w);

    double radius = 0.0;
    const std::string summary_file = (d / "summary.json").string();
    if (fs::exists(summary_file))
      {
        try
          {
            const auto j = nlohmann::json::parse(read_file(summary_file));
            if (j.contains("cavity_radius"))
              radius = j["cavity_radius"].get<double>();
            // Any cavity but the circle: its wall and channels.
            if (j.contains("cavity"))
              {
                for (const auto &p : j["cavity"].at("wall"))
                  w.wall.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
                for (const auto &c : j["cavity"].at("channels"))
                  w.channels.push_back({{c.at(0).get<double>(), c.at(1).get<double>()},
                                        {c.at(2).get<double>(), c.at(3).get<double>()}});
              }
            // The run's own L (the wire that passed the inlets), not the
            // polyline between the inlet nodes.
            if (j.contains("injected_length"))
              w.injected_length = j["injected_length"].get<double>();
          }
        catch (const nlohmann::json::exception &e)
          {
            fail(summary_file, e.what());
          }
      }
    if (options.cavity_radius)
      radius = *options.cavity_radius;
    w.cavity_radius = radius;
    return w;
  }

  core::WireState read_shape(const std::string &path, const ShapeOptions &options)
  {
    if (fs::is_directory(path))
      return read_run_directory(path, options);
    return read_shape_csv(path, options);
  }

  std::string analysis_report(core::WireState wire, const bool has_radius)
  {
    if (wire.self_contacts.empty())
      wire.self_contacts = find_self_contacts(wire);
    nlohmann::json j;
    j["points"] = wire.points.size();
    j["length"] = wire.injected_length;
    j["self_contacts"] = wire.self_contacts.size();
    j["loops"] = count_loops(wire);
    if (has_radius)
      {
        const auto m = classify(wire);
        j["cavity_radius"] = wire.cavity_radius;
        j["phi"] = packing_density(wire.injected_length, wire.cavity_radius);
        j["morphology"] = m.phase;
        for (const auto &[key, value] : morphology_numbers(m))
          j[key] = value;
      }
    else // no morphology without a cavity: every one of its keys is null
      {
        j["cavity_radius"] = j["phi"] = j["morphology"] = nullptr;
        for (const auto &[key, value] : morphology_numbers(Morphology{}))
          j[key] = nullptr;
      }
    return j.dump(2);
  }
} // namespace wirefem::analysis
