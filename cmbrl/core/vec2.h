// A small planar vector: positions and offsets on the arena floor.
#pragma once

#include <cmath>

namespace cmbrl {

struct Vec2 {
  double x = 0.0;  // metres
  double y = 0.0;  // metres

  friend Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
  friend Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
  friend Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
  friend bool operator==(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }
  friend bool operator!=(Vec2 a, Vec2 b) { return !(a == b); }
};

inline double Norm(Vec2 v) { return std::hypot(v.x, v.y); }
inline double Distance(Vec2 a, Vec2 b) { return Norm(a - b); }

}  // namespace cmbrl
