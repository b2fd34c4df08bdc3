// pteromys export: plates, DXF layout and STEP in one call.
#include <cstdio>
#include <unistd.h>

#include "pteromys/dxf_export.hpp"
#include "pteromys/fabrication.hpp"
#include "pteromys/step_export.hpp"

namespace pteromys {

nlohmann::json export_glider(const Glider& g, const ExportRequest& r) {
  const PlateSet s = slotted_plates(g, r.fabrication);
  nlohmann::json j = plates_summary(s);
  Layout layout;
  // The layout is computed (and may refuse an oversized part) before any file is written.
  layout = layout_plates(s, r.sheet);
  j["sheets"] = layout.sheets;
  j["sheet_mm"] = {r.sheet.width_m * 1000, r.sheet.height_m * 1000};
  j["fused"] = r.fused;
  j["files"] = nlohmann::json::array();
  // Each file goes to a temporary name first; both are renamed only when
  // both are complete, so a failure leaves neither behind.
  const std::string suffix = ".part-" + std::to_string(::getpid());
  std::vector<std::pair<std::string, std::string>> done;
  auto cleanup = [&]() {
    for (const auto& [tmp, final_path] : done) std::remove(tmp.c_str());
  };
  try {
    if (!r.dxf_path.empty()) {
      const std::string tmp = r.dxf_path + suffix;
      write_dxf(s, layout, tmp);
      done.emplace_back(tmp, r.dxf_path);
    }
    if (!r.step_path.empty()) {
      const std::string tmp = r.step_path + suffix;
      const StepResult sr = r.fused ? write_step_fused(g, s.thickness_m, tmp) : write_step_parts(s, tmp);
      done.emplace_back(tmp, r.step_path);
      j["step_solids"] = sr.names;
      j["step_volumes_mm3"] = sr.volumes_mm3;
    }
  } catch (...) {
    cleanup();
    throw;
  }
  for (const auto& [tmp, final_path] : done) {
    if (std::rename(tmp.c_str(), final_path.c_str()) != 0) {
      cleanup();
      throw InputError("cannot write '" + final_path + "': rename failed");
    }
    j["files"].push_back(final_path);
  }
  return j;
}

}  // namespace pteromys
