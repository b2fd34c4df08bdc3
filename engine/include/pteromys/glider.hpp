// The glider design: plates, mounts, ballast (spec/formats.md, "Glider file").
//
// One representation of a glider for the whole engine. Files and FreeCAD
// sketches are converted into it at the edge.
#pragma once

#include <string>
#include <vector>

#include "pteromys/types.hpp"

namespace pteromys {

/// Where a wing's own origin sits in the glider frame and how it is turned.
struct Mount {
  double x_m = 0.0;        ///< glider x of the wing origin [m]
  double y_m = 0.0;        ///< glider y of the wing origin [m]
  double angle_deg = 0.0;  ///< mounting angle Theta about +z [deg]; positive raises the leading edge
};

struct Wing {
  std::string name;
  /// Planform in the wing's own plane: n x 2 list of (x, z) [m]; x toward the
  /// nose, z along the span. Full span, mirror-symmetric about z = 0.
  Polygon outline;
  Mount mount;
};

struct Ballast {
  std::string name;
  double mass_kg = 0.0;
  double x_m = 0.0;  ///< glider x [m]
  double y_m = 0.0;  ///< glider y [m]
};

struct Material {
  double thickness_m = 0.001;
  double density_kg_m3 = 180.0;
};

struct Glider {
  std::string name;
  Material material;
  /// Fuselage plate: n x 2 list of (x, y) [m] in the plane of symmetry.
  Polygon fuselage;
  std::vector<Wing> wings;
  std::vector<Ballast> ballast;
};

/// Tolerances used by validation.
struct ValidationTolerances {
  double symmetry_m = 1e-4;        ///< wing mirror symmetry (spec: 0.1 mm)
  double min_edge_m = 1e-6;        ///< shorter edges count as duplicate vertices
  double min_area_m2 = 1e-8;       ///< smaller plates are degenerate
  double max_extent_m = 10.0;      ///< larger designs are almost surely in mm
};

/// Every problem found in `g`, each a sentence naming the part and the
/// problem (for example "wing 'tail' does not touch the fuselage"). Empty
/// when the glider is valid.
std::vector<std::string> validation_problems(const Glider& g,
                                             const ValidationTolerances& tol = {});

/// Throws InputError listing the problems when `validation_problems` is not empty.
void validate(const Glider& g, const ValidationTolerances& tol = {});

/// Length of the part of a wing's root chord (its section at z = 0, placed by
/// its mount) that lies inside the fuselage plate [m]; 0 when they do not touch.
double root_overlap_with_fuselage(const Glider& g, std::size_t wing_index);

/// Root chord (section z = 0) of a wing outline in wing coordinates: the
/// x-intervals [x_te, x_le] where the line z = 0 crosses the planform.
std::vector<std::pair<double, double>> root_chord_intervals(const Polygon& outline);

}  // namespace pteromys
