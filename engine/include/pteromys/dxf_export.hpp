// DXF for laser cutting (dxflib): parts laid out flat on sheets.
//
// Layers: CUT (closed LWPOLYLINEs: every hole first, then the part's outline,
// kerf-compensated), ENGRAVE (LINEs and TEXT: names, centre of gravity,
// ballast, wing positions), SHEET (the sheet borders and a caption; not to be
// cut). Units: millimetres ($INSUNITS = 4, $MEASUREMENT = 1). Sheet k (from 0)
// occupies X in [k (W + 50 mm), k (W + 50 mm) + W], Y in [0, H].
#pragma once

#include <string>
#include <vector>

#include "pteromys/fabrication.hpp"

namespace pteromys {

/// Where a plate goes: a point (u, v) of the plate maps to the sheet point
/// R(rotation) (u, v) + offset [m] (sheet-local), on sheet `sheet`.
struct Placement {
  std::size_t plate = 0;
  int sheet = 0;
  double rotation_deg = 0;  ///< 0 or 90
  Vec2 offset;
};

struct Layout {
  std::vector<Placement> placements;  ///< one per plate, in plate order
  int sheets = 0;
  SheetOptions sheet;
};

/// Shelf packing (first fit, tallest first) of the parts' cut paths on
/// sheets, each part turned by 0 or 90 degrees, at least `gap_m` apart and
/// `margin_m` from the sheet edges. Throws InputError when a part is larger
/// than the sheet in both orientations.
Layout layout_plates(const PlateSet& s, const SheetOptions& o);

/// Sheet X offset of sheet k in the DXF [m].
double sheet_x_offset(const SheetOptions& o, int k);

/// Writes the DXF (through a temporary file and a rename).
void write_dxf(const PlateSet& s, const Layout& l, const std::string& path);

}  // namespace pteromys
