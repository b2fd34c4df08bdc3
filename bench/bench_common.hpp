// Shared by the benchmarks: the bundled training gliders (examples/training).
#pragma once

#include <dirent.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "pteromys/io.hpp"

namespace pteromys::bench {

/// Every examples/training/*.glider.json, by name (without the extension), sorted.
inline std::vector<std::pair<std::string, Glider>> training_gliders() {
  static const std::string ext = ".glider.json";
  std::vector<std::string> names;
  const std::string dir = std::string(PTEROMYS_SOURCE_DIR) + "/examples/training";
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > ext.size() && n.compare(n.size() - ext.size(), ext.size(), ext) == 0) names.push_back(n);
    }
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  std::vector<std::pair<std::string, Glider>> out;
  for (const auto& n : names) out.emplace_back(n.substr(0, n.size() - ext.size()), load_glider(dir + "/" + n));
  return out;
}

}  // namespace pteromys::bench
