// The cavity's wall as one closed curve: a circle, an ellipse, or a simple
// polygon whose corners are rounded (arcs tangent to both edges), so that
// the wall is smooth everywhere. Lengths in wire diameters d; the circle
// and the ellipse are centred on the origin, the ellipse's axes along x
// and y. The cavity is the region the curve encloses.
//
// nearest() gives the wall point nearest to a point, the wall's normal
// there (pointing into the cavity) and the signed distance (positive
// inside). Where two pieces of the wall are equally near (a point on the
// medial axis, deeper in the cavity than the smallest corner radius), the
// first piece in the wall's order is taken. A polygon finds the pieces near
// a point through a grid of square cells, each listing the pieces that may
// come within one cell size of any of its points (judged by the distance
// from its centre); a point no listed piece comes that near to falls back
// to all pieces, so the result is the same as a search of all of them.
#pragma once

#include <wirefem/core/vec2.h>

#include <vector>

namespace wirefem::geometry
{
  using core::Vec2;

  /// The wall point nearest to a point p.
  struct WallPoint
  {
    Vec2 point;         ///< on the wall
    Vec2 normal;        ///< unit, into the cavity
    double depth = 0.0; ///< signed distance of p from the wall, positive inside
    /// The wall's curvature at `point` (nearest() only): positive where the
    /// wall bends round the cavity, 1/r on a circle, 0 on a straight edge.
    double curvature = 0.0;
  };

  class Cavity
  {
  public:
    enum class Shape
    {
      circle,
      ellipse,
      polygon
    };

    /// A circle of this radius (> 0).
    static Cavity circle(double radius);
    /// An ellipse with semi-axes a (along x) and b (along y), both > 0.
    static Cavity ellipse(double a, double b);
    /// A simple polygon (at least 3 vertices, either orientation) with its
    /// corners rounded to corner_radius > 0. Throws std::invalid_argument
    /// naming the fault: too few vertices, repeated or collinear vertices,
    /// edges that cross, or a corner radius whose arcs need more of an
    /// edge than it has.
    static Cavity polygon(std::vector<Vec2> vertices, double corner_radius);

    Shape shape() const { return kind; }
    WallPoint nearest(const Vec2 &p) const;
    bool contains(const Vec2 &p) const { return nearest(p).depth > 0.0; }
    /// A cheap test, without nearest(): true only if p is deeper in the
    /// cavity than delta (inside the circle of radius r - delta; the
    /// ellipse scaled by 1 - delta / b, whose gap to the wall is at least
    /// delta as the wall's support function is at least b; the disc about
    /// the polygon's centroid inside its wall, less delta, or a grid cell
    /// inside the polygon with no piece within a cell size >= delta).
    bool surely_deeper(const Vec2 &p, double delta) const;
    double area() const { return area_; }
    Vec2 centroid() const { return centroid_; }
    double perimeter() const { return perimeter_; }
    /// The wall point at arc length s from the wall's start (taken modulo
    /// the perimeter), counter-clockwise, and the normal into the cavity
    /// there. The start: (a, 0) on the circle and the ellipse; the first
    /// edge's end of its arc at the first vertex on a polygon.
    WallPoint at(double s) const;
    /// n >= 3 wall points equally spaced in arc length from the start,
    /// counter-clockwise: the wall as a polygon, for pictures and analysis.
    std::vector<Vec2> outline(int n) const;
    /// The same shape scaled by factor (> 0) about its centroid.
    Cavity scaled(double factor) const;

    /// One piece of the wall: a segment (radius 0) or an arc of a circle
    /// centred at `centre` with signed radius (positive: the centre lies
    /// inside the cavity), from angle `start` through `sweep` (signed).
    struct Piece
    {
      Vec2 from, to, centre;
      double radius = 0.0, start = 0.0, sweep = 0.0, length = 0.0;
    };

  private:
    Shape kind = Shape::circle;
    double a = 1.0, b = 1.0;    ///< circle: radius a; ellipse: semi-axes
    std::vector<Vec2> vertices; ///< polygon, counter-clockwise
    double corner_radius = 0.0;
    std::vector<Piece> pieces; ///< polygon: its wall, counter-clockwise
    /// ellipse: arc length at parameter angle k * 2 pi / n, k = 0..n
    std::vector<double> arc_table;
    double area_ = 0.0, perimeter_ = 0.0;
    double inradius_ = 0.0; ///< polygon: the depth of its centroid
    Vec2 centroid_{};
    /// polygon: the grid (see above), cells of `cell` from `grid_origin`,
    /// nx by ny, cell i's pieces at cell_pieces[cell_start[i]..cell_start[i+1]),
    /// and whether a cell without any lies inside the cavity.
    struct Grid
    {
      Vec2 origin{};
      double cell = 1.0;
      int nx = 0, ny = 0;
      std::vector<int> cell_start, cell_pieces;
      std::vector<char> inside;
      /// Cell index of p, or -1 outside the grid.
      int index(const Vec2 &p) const;
    } grid;

    void build_polygon();
    void build_grid();
    void build_ellipse();
    WallPoint nearest_on_ellipse(const Vec2 &p) const;
    WallPoint nearest_on_polygon(const Vec2 &p) const;
  };
} // namespace wirefem::geometry
