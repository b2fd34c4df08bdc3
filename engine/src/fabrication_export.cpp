// pteromys export: plates, DXF layout and STEP in one call.
#include <cstdio>
#include <unistd.h>

#include "pteromys/dxf_export.hpp"
#include "pteromys/fabrication.hpp"
#include "pteromys/io.hpp"
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
  std::vector<std::pair<std::string, std::string>> done;
  // Messages name the file the user asked for, not the temporary one.
  auto user_message = [](std::string m, const std::string& tmp, const std::string& final_path) {
    if (tmp.empty()) return m;  // no temporary file yet (temp_path_for refused the path)
    for (std::size_t at; (at = m.find(tmp)) != std::string::npos;) m.replace(at, tmp.size(), final_path);
    return m;
  };
  std::string current_tmp, current_final;
  auto cleanup = [&]() {
    for (const auto& [tmp, final_path] : done) std::remove(tmp.c_str());
  };
  try {
    if (!r.dxf_path.empty()) {
      const std::string tmp = temp_path_for(r.dxf_path, ".dxf");
      current_tmp = tmp;
      current_final = r.dxf_path;
      write_dxf(s, layout, tmp);
      done.emplace_back(tmp, r.dxf_path);
      current_tmp.clear();
    }
    if (!r.step_path.empty()) {
      const std::string tmp = temp_path_for(r.step_path, ".step");
      current_tmp = tmp;
      current_final = r.step_path;
      const StepResult sr = r.fused ? write_step_fused(g, s.thickness_m, tmp) : write_step_parts(s, tmp);
      done.emplace_back(tmp, r.step_path);
      j["step_solids"] = sr.names;
      j["step_volumes_mm3"] = sr.volumes_mm3;
    }
  } catch (const InputError& e) {
    cleanup();
    std::remove(current_tmp.c_str());
    throw InputError(user_message(e.what(), current_tmp, current_final));
  } catch (...) {
    cleanup();
    std::remove(current_tmp.c_str());
    throw;
  }
  for (const auto& [tmp, final_path] : done) {
    if (!rename_temp_into_place(tmp, final_path)) {
      cleanup();
      throw InputError("cannot write '" + final_path + "': rename failed");
    }
    j["files"].push_back(final_path);
  }
  return j;
}

}  // namespace pteromys
