// Helpers shared by the engine tests: example gliders and simple shapes.
#pragma once

#include <string>
#include <vector>

#include "pteromys/glider.hpp"

namespace pteromys::test {

/// Paths of every example glider (examples/gliders/*.glider.json).
std::vector<std::string> example_paths();
/// The examples, loaded and validated.
std::vector<std::pair<std::string, Glider>> examples();
/// Path inside the source tree.
std::string source_path(const std::string& rel);

/// Examples the default options can build: every example except those that
/// tests/data/fabrication/expected.json lists as refused (with their
/// messages, checked in tests/python/test_export.py).
bool buildable(const std::string& path);

/// Axis-aligned rectangle [x0, x1] x [y0, y1], counter-clockwise.
Polygon rect(double x0, double y0, double x1, double y1);

/// A minimal valid glider: rectangular fuselage and one rectangular wing of
/// chord c and span b mounted at (x, y, angle).
Glider simple_glider(double c = 0.06, double b = 0.4, double x = -0.05, double y = 0.0, double angle_deg = 0.0);

}  // namespace pteromys::test
