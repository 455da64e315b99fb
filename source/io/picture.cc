// Pictures of the wire in the cavity. One drawing routine renders into both a
// raster (PNG) and a vector (SVG) cairo surface so the two files always agree.
//
// Coordinates: the square [-1.05 r, 1.05 r]^2 of the scene is mapped onto the
// size_px x size_px picture, with y pointing up as in the scene. All mapping is
// done by hand (not with a cairo transformation) so that line widths and text
// sizes can be given directly in pixels.

#include <wirefem/io/picture.h>

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirefem::io
{
  namespace
  {
    struct SurfaceDeleter
    {
      void operator()(cairo_surface_t *s) const { cairo_surface_destroy(s); }
    };
    struct ContextDeleter
    {
      void operator()(cairo_t *c) const { cairo_destroy(c); }
    };
    using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
    using ContextPtr = std::unique_ptr<cairo_t, ContextDeleter>;

    /// Grey level of a segment without bending energy; the most strained
    /// segment is drawn black.
    constexpr double light_grey = 0.75;
    /// The segment with the largest contact force is this many diameters
    /// wider than the bare wire.
    constexpr double max_extra_width = 1.5;

    constexpr double pi = 3.14159265358979323846;

    /// Everything the drawing routine needs, computed once for both surfaces.
    struct Scene
    {
      double size_px = 0.0;
      double extent = 1.0;          ///< half-width of the viewed square / 1.05 (scene units)
      double scale = 1.0;           ///< pixels per scene unit
      double diameter = 1.0;        ///< wire diameter (scene units)
      bool tangential = false;      ///< channels along the wall
      std::vector<core::Vec2> wall; ///< WireState::wall
      std::vector<core::WireState::Channel> channels; ///< WireState::channels

      struct Segment
      {
        double x0, y0, x1, y1; ///< end points in pixels
        double width_px;
        double grey;
      };
      std::vector<Segment> segments; ///< in drawing order (low energy first)

      double px(const double x) const { return (x + 1.05 * extent) * scale; }
      double py(const double y) const { return (1.05 * extent - y) * scale; }
    };

    /// Mean of a per-point field over segment k, or 0 if the field is absent
    /// (wrong size). Negative and non-finite values are treated as 0: neither
    /// a force magnitude nor an energy can be negative, and a NaN must not
    /// poison the maximum used for scaling.
    double segment_value(const std::vector<double> &field, const std::size_t n_points, const std::size_t k)
    {
      if (field.size() != n_points)
        return 0.0;
      const double v = 0.5 * (field[k] + field[k + 1]);
      return (std::isfinite(v) && v > 0.0) ? v : 0.0;
    }

    /// Maps segment energies to [0,1] (0 = none, 1 = the maximum).
    ///
    /// A linear (or even square-root) map is uninformative in a crumpled wire:
    /// a few sharp folds carry energies orders of magnitude above the rest and
    /// everything else would come out in the same light grey. We therefore use
    /// t = log(1 + e/e_ref) / log(1 + e_max/e_ref) with e_ref the median of the
    /// positive segment energies: it is close to linear when energies are of
    /// similar size, and logarithmic in the ratio to the typical energy when a
    /// few points dominate, so the typical segments stay distinguishable from
    /// unstrained ones and the folds stand out.
    std::vector<double> energy_levels(const std::vector<double> &energy)
    {
      std::vector<double> positive;
      for (const double e : energy)
        if (e > 0.0)
          positive.push_back(e);

      std::vector<double> levels(energy.size(), 0.0);
      if (positive.empty())
        return levels;

      const auto mid = positive.begin() + positive.size() / 2;
      std::nth_element(positive.begin(), mid, positive.end());
      const double e_ref = *mid;
      const double e_max = *std::max_element(positive.begin(), positive.end());
      const double denominator = std::log1p(e_max / e_ref);

      for (std::size_t k = 0; k < energy.size(); ++k)
        levels[k] = std::clamp(std::log1p(energy[k] / e_ref) / denominator, 0.0, 1.0);
      return levels;
    }

    Scene make_scene(const core::WireState &wire, const int size_px)
    {
      Scene scene;
      scene.size_px = size_px;
      scene.diameter = (std::isfinite(wire.diameter) && wire.diameter > 0.0) ? wire.diameter : 1.0;

      // A broken radius must not make the picture unusable: fall back to the
      // extent of the wire itself.
      scene.wall = wire.wall;
      scene.channels = wire.channels;
      if (!wire.wall.empty())
        {
          scene.extent = 0.0;
          for (const auto &p : wire.wall)
            scene.extent = std::max(scene.extent, core::norm(p));
        }
      else if (std::isfinite(wire.cavity_radius) && wire.cavity_radius > 0.0)
        scene.extent = wire.cavity_radius;
      else
        {
          double r = 0.0;
          for (const auto &p : wire.points)
            if (std::isfinite(p.x) && std::isfinite(p.y))
              r = std::max(r, core::norm(p));
          scene.extent = r > 0.0 ? r : 1.0;
        }
      scene.scale = size_px / (2.1 * scene.extent);

      const std::size_t n_points = wire.points.size();
      const std::size_t n_segments = n_points < 2 ? 0 : n_points - 1;

      std::vector<double> force(n_segments), energy(n_segments);
      for (std::size_t k = 0; k < n_segments; ++k)
        {
          force[k] = segment_value(wire.contact_force, n_points, k);
          energy[k] = segment_value(wire.bending_energy, n_points, k);
        }
      const double f_max = n_segments ? *std::max_element(force.begin(), force.end()) : 0.0;
      const std::vector<double> level = energy_levels(energy);

      // The wire is drawn with its true thickness so contacts look like
      // contacts; below one pixel it would vanish, hence the floor.
      const double base_px = std::max(1.0, scene.diameter * scene.scale);
      const double extra_px = max_extra_width * scene.diameter * scene.scale;

      // Strained segments are drawn last so that their dark colour is not
      // hidden under the round caps of their lighter neighbours.
      std::vector<std::size_t> order(n_segments);
      std::iota(order.begin(), order.end(), std::size_t(0));
      std::stable_sort(order.begin(), order.end(),
                       [&](const std::size_t a, const std::size_t b) { return energy[a] < energy[b]; });

      for (const std::size_t k : order)
        {
          const auto &a = wire.points[k];
          const auto &b = wire.points[k + 1];
          if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y))
            continue;
          Scene::Segment s;
          s.x0 = scene.px(a.x);
          s.y0 = scene.py(a.y);
          s.x1 = scene.px(b.x);
          s.y1 = scene.py(b.y);
          s.width_px = base_px + (f_max > 0.0 ? extra_px * force[k] / f_max : 0.0);
          s.grey = light_grey * (1.0 - level[k]);
          scene.segments.push_back(s);
        }
      return scene;
    }

    /// The wire and the caption over the cavity already drawn.
    void draw_wire(cairo_t *cr, const Scene &scene, const std::string &caption)
    {
      const double size = scene.size_px;
      // Wire: one stroke per segment, because width and colour vary along it.
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
      for (const auto &s : scene.segments)
        {
          cairo_set_source_rgb(cr, s.grey, s.grey, s.grey);
          cairo_set_line_width(cr, s.width_px);
          cairo_move_to(cr, s.x0, s.y0);
          cairo_line_to(cr, s.x1, s.y1);
          cairo_stroke(cr);
        }

      if (!caption.empty())
        {
          const double font_px = std::max(10.0, size / 60.0);
          cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
          cairo_set_font_size(cr, font_px);
          cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
          cairo_move_to(cr, 0.5 * font_px, size - 0.6 * font_px);
          cairo_show_text(cr, caption.c_str());
        }
    }

    /// Any cavity (WireState::wall): each channel a light strip of width d
    /// from its inlet back out of the picture, and the wall as a polygon,
    /// left open across the channels' mouths.
    void draw_shaped_wall(cairo_t *cr, const Scene &scene, const double thin_px)
    {
      const double d = scene.diameter, far = 4.0 * scene.extent;
      const auto across = [&](const core::WireState::Channel &c, const core::Vec2 &p) {
        return core::cross(c.axis, p - c.inlet);
      };
      for (const auto &c : scene.channels)
        {
          const core::Vec2 side = (0.5 * d) * core::perp(c.axis), back = far * c.axis;
          const core::Vec2 corner[4] = {c.inlet + side, c.inlet + side - back, c.inlet - side - back,
                                        c.inlet - side};
          cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
          cairo_move_to(cr, scene.px(corner[0].x), scene.py(corner[0].y));
          for (int k = 1; k < 4; ++k)
            cairo_line_to(cr, scene.px(corner[k].x), scene.py(corner[k].y));
          cairo_close_path(cr);
          cairo_fill(cr);
          cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
          cairo_set_line_width(cr, thin_px);
          for (const int k : {0, 2})
            {
              cairo_move_to(cr, scene.px(corner[k].x), scene.py(corner[k].y));
              cairo_line_to(cr, scene.px(corner[k + 1].x), scene.py(corner[k + 1].y));
            }
          cairo_stroke(cr);
        }
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      cairo_set_line_width(cr, thin_px);
      const std::size_t n = scene.wall.size();
      for (std::size_t k = 0; k < n; ++k)
        {
          const core::Vec2 a = scene.wall[k], b = scene.wall[(k + 1) % n], m = 0.5 * (a + b);
          bool open = false;
          for (const auto &c : scene.channels)
            open |= std::abs(across(c, m)) < 0.5 * d &&
                    std::abs(core::dot(c.axis, m - c.inlet)) < 0.25 * scene.extent;
          if (open)
            continue;
          cairo_move_to(cr, scene.px(a.x), scene.py(a.y));
          cairo_line_to(cr, scene.px(b.x), scene.py(b.y));
        }
      cairo_stroke(cr);
    }

    void draw(cairo_t *cr, const Scene &scene, const std::string &caption)
    {
      const double size = scene.size_px;
      const double r = scene.extent;
      const double d = scene.diameter;
      const double thin_px = std::max(1.0, 0.002 * size);

      cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
      cairo_paint(cr);

      // Channels: a light strip of width d from the cavity wall to the edge
      // of the picture, bounded by two walls; tangential ones run along the
      // wall from the inlets (-r + d/2, 0) up and (r - d/2, 0) down.
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
      // The strip between pixel corners (x0, y0) and (x1, y1), with its
      // walls along its length (vertical or horizontal).
      const auto strip = [&](const double x0, const double y0, const double x1, const double y1,
                             const bool vertical) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_rectangle(cr, std::min(x0, x1), std::min(y0, y1), std::abs(x1 - x0), std::abs(y1 - y0));
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        cairo_set_line_width(cr, thin_px);
        for (const double w : {0.0, 1.0})
          {
            cairo_move_to(cr, vertical ? x0 + w * (x1 - x0) : x0, vertical ? y0 : y0 + w * (y1 - y0));
            cairo_line_to(cr, vertical ? x0 + w * (x1 - x0) : x1, vertical ? y1 : y0 + w * (y1 - y0));
          }
        cairo_stroke(cr);
      };
      if (!scene.wall.empty())
        {
          draw_shaped_wall(cr, scene, thin_px);
          draw_wire(cr, scene, caption);
          return;
        }
      for (const double side : {-1.0, 1.0})
        if (scene.tangential)
          strip(scene.px(side * r), scene.py(0.0), scene.px(side * (r - d)), side < 0 ? 0.0 : size, true);
        else
          strip(scene.px(side * r), scene.py(0.5 * d), side > 0 ? size : 0.0, scene.py(-0.5 * d), false);

      // Cavity wall, left open where the channels enter. The gaps are
      // symmetric about the x axis, so the orientation of the (flipped) pixel
      // angles does not matter.
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      cairo_set_line_width(cr, thin_px);
      const double cx = scene.px(0.0), cy = scene.py(0.0), radius_px = r * scene.scale;
      if (!scene.tangential && d < 2.0 * r)
        {
          const double gap = std::asin(0.5 * d / r);
          cairo_new_sub_path(cr);
          cairo_arc(cr, cx, cy, radius_px, gap, pi - gap);
          cairo_new_sub_path(cr);
          cairo_arc(cr, cx, cy, radius_px, pi + gap, 2.0 * pi - gap);
        }
      else
        cairo_arc(cr, cx, cy, radius_px, 0.0, 2.0 * pi);
      cairo_stroke(cr);

      draw_wire(cr, scene, caption);
    }

    void check(const cairo_status_t status, const std::string &what, const std::string &file)
    {
      if (status != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error("wirefem::io::write_pictures: cannot " + what + " '" + file +
                                 "': " + cairo_status_to_string(status));
    }

    /// Draws on a fresh context and reports any error the context collected.
    void render(cairo_surface_t *surface, const std::function<void(cairo_t *)> &draw_on,
                const std::string &file)
    {
      const ContextPtr cr(cairo_create(surface));
      draw_on(cr.get());
      check(cairo_status(cr.get()), "draw", file);
    }

    /// The same drawing as a PNG and an SVG file of width x height pixels.
    void write_png_and_svg(const int width, const int height, const std::function<void(cairo_t *)> &draw_on,
                           const std::string &png_file, const std::string &svg_file)
    {
      {
        const SurfacePtr png(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height));
        check(cairo_surface_status(png.get()), "create image for", png_file);
        render(png.get(), draw_on, png_file);
        check(cairo_surface_write_to_png(png.get(), png_file.c_str()), "write", png_file);
      }
      {
        // The SVG surface writes lazily; errors opening or writing the file
        // only show up in the surface status, checked at each stage.
        const SurfacePtr svg(cairo_svg_surface_create(svg_file.c_str(), width, height));
        check(cairo_surface_status(svg.get()), "open", svg_file);
        cairo_svg_surface_set_document_unit(svg.get(), CAIRO_SVG_UNIT_PX);
        render(svg.get(), draw_on, svg_file);
        cairo_surface_finish(svg.get());
        check(cairo_surface_status(svg.get()), "write", svg_file);
      }
    }
  } // namespace

  void write_pictures(const core::WireState &wire, const std::string &png_file, const std::string &svg_file,
                      const PictureOptions &options)
  {
    if (options.size_px <= 0)
      throw std::invalid_argument("wirefem::io::write_pictures: size_px must be positive, got " +
                                  std::to_string(options.size_px));

    Scene scene = make_scene(wire, options.size_px);
    scene.tangential = options.tangential_channels;
    write_png_and_svg(
        options.size_px, options.size_px, [&](cairo_t *cr) { draw(cr, scene, options.caption); }, png_file,
        svg_file);
  }

  void write_phase_diagram(const PhaseDiagram &diagram, const std::string &png_file,
                           const std::string &svg_file)
  {
    const int rows = static_cast<int>(diagram.kappa.size()), cols = static_cast<int>(diagram.mu.size());
    if (rows == 0 || cols == 0 || static_cast<int>(diagram.cells.size()) != rows * cols)
      throw std::invalid_argument("wirefem::io::write_phase_diagram: cells do not match the grid");
    const double cell = 120.0, left = 110.0, bottom = 70.0, top = 75.0, right = 20.0;
    const int width = static_cast<int>(left + cols * cell + right);
    const int height = static_cast<int>(top + rows * cell + bottom);
    auto colour = [](const std::string &phase, double rgb[3]) {
      const double spiral[3] = {0.35, 0.55, 0.85}, classic[3] = {0.40, 0.75, 0.40},
                   plastic[3] = {0.90, 0.45, 0.35}, none[3] = {0.85, 0.85, 0.85};
      const double *c = phase == "spiral"    ? spiral
                        : phase == "classic" ? classic
                        : phase == "plastic" ? plastic
                                             : none;
      std::copy(c, c + 3, rgb);
    };
    auto text = [](cairo_t *cr, const std::string &t, const double x, const double y, const double size,
                   const bool centre) {
      cairo_set_font_size(cr, size);
      cairo_text_extents_t e;
      cairo_text_extents(cr, t.c_str(), &e);
      cairo_move_to(cr, centre ? x - 0.5 * e.width - e.x_bearing : x, y);
      cairo_show_text(cr, t.c_str());
    };
    auto number = [](const double v) {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%.4g", v);
      return std::string(buffer);
    };
    write_png_and_svg(
        width, height,
        [&](cairo_t *cr) {
          cairo_set_source_rgb(cr, 1, 1, 1);
          cairo_paint(cr);
          cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
          for (int i = 0; i < rows; ++i) // kappa grows upwards
            for (int j = 0; j < cols; ++j)
              {
                const auto &c = diagram.cells[i * cols + j];
                const double x = left + j * cell, y = top + (rows - 1 - i) * cell;
                double rgb[3];
                colour(c.majority, rgb);
                // Paler where the majority is slim.
                const double f = c.runs > 0 ? 0.4 + 0.6 * c.fraction : 0.0;
                cairo_set_source_rgb(cr, 1 - f * (1 - rgb[0]), 1 - f * (1 - rgb[1]), 1 - f * (1 - rgb[2]));
                cairo_rectangle(cr, x, y, cell, cell);
                cairo_fill_preserve(cr);
                cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
                cairo_set_line_width(cr, 1.0);
                cairo_stroke(cr);
                cairo_set_source_rgb(cr, 0, 0, 0);
                text(cr, c.runs > 0 ? c.majority : "no runs", x + 0.5 * cell, y + 0.45 * cell, 15, true);
                text(cr, std::to_string(c.votes) + "/" + std::to_string(c.runs), x + 0.5 * cell,
                     y + 0.68 * cell, 13, true);
              }
          cairo_set_source_rgb(cr, 0, 0, 0);
          for (int j = 0; j < cols; ++j)
            text(cr, number(diagram.mu[j]), left + (j + 0.5) * cell, top + rows * cell + 22, 13, true);
          for (int i = 0; i < rows; ++i)
            text(cr, number(diagram.kappa[i]), 10, top + (rows - 1 - i + 0.5) * cell + 5, 13, false);
          text(cr, "static friction mu_st", left + 0.5 * cols * cell, height - 15, 14, true);
          text(cr, "yield curvature kappa_theta (rows)", 10, 62, 14, false);
          text(cr, diagram.title, 0.5 * width, 24, 14, true);
        },
        png_file, svg_file);
  }
} // namespace wirefem::io
