// A plain 2D vector for the hot loops of the models and the contact module.
// Units are those of the caller (lengths in wire diameters d throughout wirefem).
#pragma once

#include <cmath>

namespace wirefem::core
{
  struct Vec2
  {
    double x = 0.0;
    double y = 0.0;

    constexpr Vec2 &operator+=(const Vec2 &o)
    {
      x += o.x;
      y += o.y;
      return *this;
    }
    constexpr Vec2 &operator-=(const Vec2 &o)
    {
      x -= o.x;
      y -= o.y;
      return *this;
    }
    constexpr Vec2 &operator*=(const double a)
    {
      x *= a;
      y *= a;
      return *this;
    }
  };

  constexpr Vec2 operator+(Vec2 a, const Vec2 &b)
  {
    return a += b;
  }
  constexpr Vec2 operator-(Vec2 a, const Vec2 &b)
  {
    return a -= b;
  }
  constexpr Vec2 operator-(const Vec2 &a)
  {
    return {-a.x, -a.y};
  }
  constexpr Vec2 operator*(const double s, Vec2 a)
  {
    return a *= s;
  }
  constexpr Vec2 operator*(Vec2 a, const double s)
  {
    return a *= s;
  }

  constexpr double dot(const Vec2 &a, const Vec2 &b)
  {
    return a.x * b.x + a.y * b.y;
  }
  /// z-component of the 3D cross product: positive when b is counter-clockwise of a.
  constexpr double cross(const Vec2 &a, const Vec2 &b)
  {
    return a.x * b.y - a.y * b.x;
  }
  /// a rotated by +90 degrees (counter-clockwise).
  constexpr Vec2 perp(const Vec2 &a)
  {
    return {-a.y, a.x};
  }
  /// |a|; plain sqrt, not std::hypot: no coordinate here is near
  /// overflow, and hypot costs several times as much.
  inline double norm(const Vec2 &a)
  {
    return std::sqrt(a.x * a.x + a.y * a.y);
  }
  constexpr double norm_square(const Vec2 &a)
  {
    return a.x * a.x + a.y * a.y;
  }
} // namespace wirefem::core
