// STEP for 3D printing and CAD exchange (OpenCASCADE, XCAF).
//
// Geometry in millimetres (the STEP unit), in the glider frame: x toward the
// nose, y up, z along the span. Each plate is its finished outline (with
// slots and holes, no kerf) extruded across its thickness, centred on its
// mid-plane, and placed by its transform; each solid is named after its
// plate. The fused option writes the unslotted plates fused into one solid.
#pragma once

#include <string>
#include <vector>

#include "pteromys/fabrication.hpp"

namespace pteromys {

struct StepResult {
  std::vector<std::string> names;  ///< names of the solids written
  std::vector<double> volumes_mm3; ///< their volumes
};

/// One named solid per plate of `s`.
StepResult write_step_parts(const PlateSet& s, const std::string& path);

/// One solid: the fuselage and every whole wing as designed (no slots),
/// fused (BRepAlgoAPI_Fuse). Throws InputError when the result is not a single
/// solid (a part that does not touch the rest).
StepResult write_step_fused(const Glider& g, double thickness_m, const std::string& path);

}  // namespace pteromys
