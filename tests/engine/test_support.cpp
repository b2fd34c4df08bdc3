#include "test_support.hpp"

#include <nlohmann/json.hpp>

#include "pteromys/io.hpp"

namespace pteromys::test {

std::string source_path(const std::string& rel) { return std::string(PTEROMYS_SOURCE_DIR) + "/" + rel; }

std::vector<std::string> example_paths() { return glider_files_in(source_path("examples/gliders")); }

std::vector<std::pair<std::string, Glider>> examples() {
  std::vector<std::pair<std::string, Glider>> out;
  for (const auto& p : example_paths()) out.emplace_back(p, load_glider(p));
  return out;
}

/// Examples the default options can build: every example except those that
/// tests/data/fabrication/expected.json lists as refused (with their
/// messages, checked in tests/python/test_export.py).
bool buildable(const std::string& path) {
  static const std::vector<std::string> refused = [] {
    std::vector<std::string> out;
    const auto j = nlohmann::json::parse(read_file(test::source_path("tests/data/fabrication/expected.json")));
    for (const auto& [name, c] : j.items()) {
      const std::string g = c.at("glider").get<std::string>();
      if (c.at("args").empty() && g.find("examples/gliders/") != std::string::npos)
        out.push_back(g.substr(g.find_last_of('/') + 1));
    }
    return out;
  }();
  for (const auto& r : refused)
    if (path.size() >= r.size() && path.compare(path.size() - r.size(), r.size(), r) == 0) return false;
  return true;
}

Polygon rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

Glider simple_glider(double c, double b, double x, double y, double angle_deg) {
  Glider g;
  g.name = "simple";
  g.material = {0.001, 200.0};
  g.fuselage = rect(-0.3, -0.01, 0.0, 0.01);
  Wing w;
  w.name = "main";
  w.outline = rect(-c, -b / 2, 0.0, b / 2);
  w.mount = {x, y, angle_deg};
  g.wings.push_back(w);
  return g;
}

}  // namespace pteromys::test
