// Wing elements (paper section 4.2): a planform sliced perpendicular to z.
#pragma once

#include <string>
#include <vector>

#include "pteromys/types.hpp"

namespace pteromys {

/// One wing element: a trapezoid-like slice of a planform between two cut
/// lines z = z0 and z = z1 (wing coordinates; x toward the nose).
struct WingElement {
  double z0 = 0, z1 = 0;  ///< spanwise extent [m], z0 < z1
  double area = 0;        ///< exact area of the planform inside the slice [m^2]
  double chord = 0;       ///< mean chord l = area / (z1 - z0) [m]
  double x_le = 0;        ///< mean leading-edge x over the slice [m]
  double x_qc = 0;        ///< quarter-chord point p: x_le - chord / 4 [m]
  /// Sweep of the leading and trailing edges [rad], from the edge positions at
  /// the slice's inboard and outboard cut lines: positive when the edge moves
  /// aft (toward -x) going outboard (away from z = 0). A rectangle has 0, 0;
  /// a swept-back wing has both positive; a delta has xi_l > 0, xi_t = 0.
  double xi_l = 0, xi_t = 0;
  /// 0 for the most upstream piece of planform in this slice; k > 0 for the
  /// k-th piece behind it in the same streamline (the paper's model ignores
  /// the interference between such pieces).
  int streamline_rank = 0;
};

struct WingElements {
  std::vector<WingElement> elements;  ///< ordered by z, then by streamline rank
  double planform_area = 0;            ///< exact area of the outline [m^2]
  double span = 0;                     ///< z extent [m]
  /// True when some slice cuts the planform more than once along x.
  bool multiple_in_streamline = false;
  /// Spanwise ranges [z0, z1] where that happens (merged).
  std::vector<std::pair<double, double>> multiple_ranges;
};

/// Slices a simple polygon (any orientation, convex or not) into elements.
/// Cut lines lie at z = k * dz for integers k (so the slicing is symmetric
/// about z = 0); vertices between cut lines are handled exactly: element
/// areas sum to the planform area up to rounding. Where a cut crosses the
/// planform several times, each piece becomes its own element.
///
/// @param outline wing planform, n x 2 list of (x, z) [m]
/// @param dz      spacing of the cut lines [m], > 0
WingElements slice_wing(const Polygon& outline, double dz);

}  // namespace pteromys
