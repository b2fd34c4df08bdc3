// Private to the engine's sources: reading a JSON file's values with messages
// that name the file and the key path ("glider file x.json: wings[0].mount.x_m
// is not a finite number"). Shared by the glider and model files (io.cpp) and
// the calibration files (capture_io.cpp).
#pragma once

#include <array>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "pteromys/types.hpp"

namespace pteromys {
namespace detail {

struct JsonReader {
  std::string where;  // "" or a prefix such as "glider file x.json: "

  [[noreturn]] void fail(const std::string& msg) const { throw InputError(where + msg); }

  static std::string join(const std::string& path, const char* k) { return path.empty() ? std::string(k) : path + "." + k; }

  const nlohmann::json& key(const nlohmann::json& obj, const char* k, const std::string& path) const {
    if (!obj.is_object()) fail((path.empty() ? std::string("the file") : path) + " must be a JSON object");
    auto it = obj.find(k);
    if (it == obj.end()) fail("missing key '" + join(path, k) + "'");
    return *it;
  }
  double number(const nlohmann::json& v, const std::string& path) const {
    if (v.is_null()) fail(path + " is null (NaN is not allowed)");
    if (!v.is_number()) fail(path + " must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path + " is not a finite number");
    return d;
  }
  double number(const nlohmann::json& obj, const char* k, const std::string& path) const {
    return number(key(obj, k, path), join(path, k));
  }
  std::string string(const nlohmann::json& obj, const char* k, const std::string& path) const {
    const nlohmann::json& v = key(obj, k, path);
    if (!v.is_string()) fail(join(path, k) + " must be a string");
    return v.get<std::string>();
  }
  Vec2 pair(const nlohmann::json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 2) fail(path + " must be a pair of numbers [a, b]");
    return {number(v[0], path + "[0]"), number(v[1], path + "[1]")};
  }
  Polygon polygon(const nlohmann::json& v, const std::string& path) const {
    if (!v.is_array()) fail(path + " must be a list of [x, y] pairs");
    Polygon p;
    for (std::size_t i = 0; i < v.size(); ++i) p.push_back(pair(v[i], path + "[" + std::to_string(i) + "]"));
    return p;
  }
  /// A 3 x 3 matrix written as three rows, row-major.
  std::array<double, 9> mat3(const nlohmann::json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 3) fail(path + " must be a 3 x 3 list of numbers");
    std::array<double, 9> m{};
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_array() || v[i].size() != 3) fail(path + " must be a 3 x 3 list of numbers");
      for (int j = 0; j < 3; ++j)
        m[3 * i + j] = number(v[i][j], path + "[" + std::to_string(i) + "][" + std::to_string(j) + "]");
    }
    return m;
  }
};

}  // namespace detail
}  // namespace pteromys
