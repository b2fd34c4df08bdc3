// Basic value types shared by every part of the engine.
//
// Units: SI throughout (metres, kilograms, seconds, radians). Angles stored in
// structs are radians unless the member name ends in `_deg`.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace pteromys {

constexpr double kPi = 3.14159265358979323846;
inline constexpr double deg2rad(double d) { return d * kPi / 180.0; }
inline constexpr double rad2deg(double r) { return r * 180.0 / kPi; }
/// An angle wrapped to (-pi, pi] [rad].
inline double wrap_angle(double a) {
  if (a > kPi || a <= -kPi) {  // rare: only after a loop
    a = std::fmod(a + kPi, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    a -= kPi;
  }
  return a;
}

/// A point or vector in a plane. In the glider frame (x toward the nose, y up);
/// in a wing's own plane the second coordinate is the span coordinate z.
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
/// Rotate `a` counter-clockwise (about +z) by the angle whose cosine and
/// sine are `c` and `s` (computed once for several vectors).
inline Vec2 rotate(Vec2 a, double c, double s) { return {c * a.x - s * a.y, s * a.x + c * a.y}; }
/// Rotate `a` counter-clockwise (about +z) by `angle` radians.
inline Vec2 rotate(Vec2 a, double angle) { return rotate(a, std::cos(angle), std::sin(angle)); }

/// Closed polygon: n x 2 list of vertices, the last joins the first (not repeated).
using Polygon = std::vector<Vec2>;

/// Air and gravity. Defaults: sea-level air at about 20 C, standard gravity.
struct Environment {
  double air_density = 1.2;     ///< kg/m^3
  double air_viscosity = 1.8e-5;  ///< Pa s (dynamic)
  double gravity = 9.81;        ///< m/s^2
};

/// Raised for input a person supplied that cannot be used (malformed file,
/// invalid geometry, impossible option). The message names the problem in
/// plain words and is meant to be shown to the person as it is.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pteromys
