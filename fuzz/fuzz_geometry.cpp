// Fuzz target: the geometry pipeline behind a glider file — outline
// validation, slicing into wing elements (paper §4.2) and the slotted plates
// of fabrication. The input bytes become a fuselage outline, one or two
// mirror-symmetric wings and their mounts, on a 5 mm grid (so that near-
// degenerate shapes are common). Oracle: a glider that validates slices into
// elements whose areas sum to each wing's area, and its plates either build
// or are refused with an InputError.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "pteromys/elements.hpp"
#include "pteromys/fabrication.hpp"
#include "pteromys/geometry.hpp"
#include "pteromys/glider.hpp"
#include "pteromys/io.hpp"

using namespace pteromys;
using pteromys_fuzz::accepts;
using pteromys_fuzz::fuzz_abort;

namespace {

struct Bytes {
  const uint8_t* p;
  size_t n, i = 0;
  int next() { return i < n ? p[i++] : 0; }
  double coord(double scale) { return (static_cast<int8_t>(next())) * scale; }
};

double shoelace(const Polygon& poly) {
  double a = 0;
  for (size_t i = 0; i < poly.size(); ++i) a += cross(poly[i], poly[(i + 1) % poly.size()]);
  return 0.5 * std::fabs(a);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes b{data, size};
  const double s = 0.005;  // 5 mm grid, +-0.64 m
  Glider g;
  g.name = "fuzz";
  g.material.thickness_m = 0.001 + 0.0005 * (b.next() % 12);
  g.material.density_kg_m3 = 20.0 + 10.0 * (b.next() % 50);
  const int nf = 3 + b.next() % 10;
  for (int k = 0; k < nf; ++k) g.fuselage.push_back({b.coord(s), b.coord(s)});
  const int nw = 1 + b.next() % 2;
  for (int w = 0; w < nw; ++w) {
    Wing wing;
    wing.name = w == 0 ? "main" : "tail";
    // Half outline from root to tip (z >= 0), mirrored: symmetric by construction.
    const int nh = 1 + b.next() % 5;
    std::vector<Vec2> half;
    const double x0 = b.coord(s), x1 = b.coord(s);
    for (int k = 0; k < nh; ++k) half.push_back({b.coord(s), std::fabs(b.coord(s))});
    wing.outline.push_back({x0, 0.0});
    for (const auto& p : half) wing.outline.push_back(p);
    wing.outline.push_back({x1, 0.0});
    for (int k = nh - 1; k >= 0; --k) wing.outline.push_back({half[k].x, -half[k].y});
    wing.mount.x_m = b.coord(s);
    wing.mount.y_m = b.coord(0.001);
    wing.mount.angle_deg = b.coord(0.2);
    g.wings.push_back(wing);
  }
  if (b.next() & 1) g.ballast.push_back({"clip", 0.0005 * (b.next() % 20), b.coord(s), b.coord(0.001)});

  // Validation goes through the file reader, as a user's file would.
  Glider v;
  if (!accepts([&] {
        v = glider_from_json(glider_to_json(g));
        validate(v);
      }))
    return 0;
  for (const auto& w : v.wings) {
    WingElements el;
    if (!accepts([&] { el = slice_wing(w.outline, 0.005); }))
      fuzz_abort("a validated wing cannot be sliced");
    double sum = 0;
    for (const auto& e : el.elements) sum += e.area;
    const double area = shoelace(w.outline);
    if (!(std::fabs(sum - area) <= 1e-9 + 1e-6 * area))
      fuzz_abort("element areas sum to " + std::to_string(sum) + ", the wing's area is " + std::to_string(area));
  }
  const bool built = accepts([&] { (void)slotted_plates(v); });
  if (std::getenv("PTEROMYS_FUZZ_VERBOSE")) std::fprintf(stderr, "valid glider; plates %s\n", built ? "built" : "refused");
  return 0;
}
