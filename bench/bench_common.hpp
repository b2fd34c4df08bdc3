// Shared by the benchmarks: the bundled example and training gliders.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "pteromys/io.hpp"

namespace pteromys::bench {

/// A glider file's name without its folder and ".glider.json".
inline std::string short_name(const std::string& path) {
  static const std::string ext = ".glider.json";
  const auto s = path.find_last_of('/');
  std::string n = s == std::string::npos ? path : path.substr(s + 1);
  if (n.size() > ext.size() && n.compare(n.size() - ext.size(), ext.size(), ext) == 0) n.resize(n.size() - ext.size());
  return n;
}

/// Paths of every examples/gliders/*.glider.json, sorted.
inline std::vector<std::string> example_paths() {
  return glider_files_in(std::string(PTEROMYS_SOURCE_DIR) + "/examples/gliders");
}

/// Every examples/training/*.glider.json, by name (without the extension), sorted.
inline std::vector<std::pair<std::string, Glider>> training_gliders() {
  std::vector<std::pair<std::string, Glider>> out;
  for (const auto& p : glider_files_in(std::string(PTEROMYS_SOURCE_DIR) + "/examples/training"))
    out.emplace_back(short_name(p), load_glider(p));
  return out;
}

}  // namespace pteromys::bench
