#include "pteromys/dataset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <sys/stat.h>

#include "pteromys/io.hpp"

namespace pteromys {
using nlohmann::json;

namespace {

std::string join(const std::string& dir, const std::string& rel) {
  if (!rel.empty() && rel[0] == '/') return rel;
  return dir + "/" + rel;
}

void make_dirs(const std::string& path) {
  std::string cur;
  std::stringstream ss(path);
  std::string part;
  if (!path.empty() && path[0] == '/') cur = "/";
  while (std::getline(ss, part, '/')) {
    if (part.empty()) continue;
    cur += part + "/";
    struct stat st {};
    if (stat(cur.c_str(), &st) != 0 && mkdir(cur.c_str(), 0755) != 0)
      throw InputError("cannot create directory '" + cur + "'");
  }
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// A number as a person reads it (6 significant digits).
std::string short_num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// What a dataset of tracked hand-launched glides can hold (dataset_problems).
constexpr double kMaxFlightS = 60.0;        ///< first to last tracked point of a flight [s]
constexpr double kMaxGapS = 2.0;            ///< between two tracked points of a flight [s]
constexpr double kMaxPositionM = 10000.0;   ///< |x|, |y| of a tracked point [m]
constexpr double kMaxTrackingSigmaM = 10.0; ///< tracking noise [m]
constexpr double kMinTrackingSigmaM = 1e-9; ///< below it the noise's square underflows the chi-square sums
// Where hand-launched gliders fly (a unit slip, g in cm/s^2 or a density in
// g/m^3, makes fits that report nonsense or overflow): the Moon's gravity to
// Jupiter's, and air from 15 km up to twice sea level's density and
// viscosity ranges that cover every gas a glider could fly in.
constexpr double kGravityRange[2] = {1.0, 30.0};         ///< [m/s^2]
constexpr double kAirDensityRange[2] = {0.1, 5.0};       ///< [kg/m^3]
constexpr double kAirViscosityRange[2] = {1e-6, 1e-3};   ///< [Pa s]

}  // namespace

std::vector<std::string> dataset_problems(const Dataset& d) {
  std::vector<std::string> out;
  for (double v : {d.frame_rate_hz, d.tracking_sigma_m, d.air_density, d.air_viscosity, d.gravity})
    if (!std::isfinite(v) || v <= 0) {
      out.push_back("frame_rate_hz, tracking_sigma_m, air density and viscosity and gravity must be positive numbers");
      break;
    }
  if (d.tracking_sigma_m > kMaxTrackingSigmaM && std::isfinite(d.tracking_sigma_m))
    out.push_back("tracking_sigma_m is " + short_num(d.tracking_sigma_m) + " m: the tracking noise is in metres (at most " +
                  short_num(kMaxTrackingSigmaM) + " m is read)");
  if (d.tracking_sigma_m > 0 && d.tracking_sigma_m < kMinTrackingSigmaM)
    out.push_back("tracking_sigma_m is " + short_num(d.tracking_sigma_m) + " m: the tracking noise is in metres (at least " +
                  short_num(kMinTrackingSigmaM) + " m is read)");
  auto in_range = [&](double v, const double (&r)[2], const std::string& key, const std::string& what) {
    if (std::isfinite(v) && v > 0 && (v < r[0] || v > r[1]))
      out.push_back(key + " is " + short_num(v) + ": " + what + " (" + short_num(r[0]) + " to " + short_num(r[1]) +
                    " is read)");
  };
  in_range(d.gravity, kGravityRange, "gravity_m_s2", "gravity is in m/s^2, 9.81 on Earth");
  in_range(d.air_density, kAirDensityRange, "air.density_kg_m3", "the air's density is in kg/m^3, 1.2 at sea level");
  in_range(d.air_viscosity, kAirViscosityRange, "air.viscosity_pa_s", "the air's viscosity is in Pa s, 1.8e-05 for air");
  std::set<std::string> names;
  for (const auto& f : d.flights) {
    const std::string w = "flight '" + f.name + "'";
    if (f.name.empty()) out.push_back("a flight has no name");
    if (!names.insert(f.name).second) out.push_back(w + " appears twice");
    if (!d.gliders.count(f.glider)) out.push_back(w + " refers to unknown glider key '" + f.glider + "'");
    if (f.points.size() < 6)
      out.push_back(w + " has " + std::to_string(f.points.size()) + " points; at least 6 are needed");
    std::string gap;  // the first gap between points longer than kMaxGapS
    for (std::size_t i = 0; i < f.points.size(); ++i) {
      const auto& p = f.points[i];
      if (!std::isfinite(p.t) || !std::isfinite(p.x) || !std::isfinite(p.y)) {
        out.push_back(w + " point " + std::to_string(i) + " has a NaN or infinite value");
        break;
      }
      if (i > 0 && !(p.t > f.points[i - 1].t)) {
        out.push_back(w + ": time does not increase at point " + std::to_string(i) + " (t = " +
                      fmt(f.points[i - 1].t) + " then " + fmt(p.t) + " s)");
        break;
      }
      if (i > 0 && p.t - f.points[i - 1].t > kMaxGapS && gap.empty())
        gap = w + " has no point for " + short_num(p.t - f.points[i - 1].t) + " s (t = " +
              short_num(f.points[i - 1].t) + " to " + short_num(p.t) +
              " s): a glide is tracked frame by frame, so this is a stray point or two flights under one name (at "
              "most " + short_num(kMaxGapS) + " s between points is read)";
      // Units: a position in millimetres or a time in milliseconds makes
      // flights that every fit would simulate for hours.
      if (std::abs(p.x) > kMaxPositionM || std::abs(p.y) > kMaxPositionM) {
        out.push_back(w + " point " + std::to_string(i) + " is at (" + short_num(p.x) + ", " + short_num(p.y) +
                      ") m: positions are in metres, and a tracked glide spans metres to tens of metres (at most " +
                      short_num(kMaxPositionM) + " m from the origin is read)");
        break;
      }
    }
    // (times in milliseconds also leave gaps: the span is the message then)
    if (f.points.size() >= 2 && f.points.back().t - f.points.front().t > kMaxFlightS)
      out.push_back(w + " spans " + short_num(f.points.back().t - f.points.front().t) +
                    " s from its first to its last point: times are in seconds, and a tracked hand-launched glide "
                    "lasts seconds (at most " + short_num(kMaxFlightS) + " s is read)");
    else if (!gap.empty())
      out.push_back(gap);
  }
  if (d.flights.empty()) out.push_back("the dataset has no flights");
  return out;
}

std::vector<std::string> dataset_files(const std::string& dataset_json, const Dataset& d) {
  const std::string dir = directory_of(dataset_json);
  std::vector<std::string> out{dataset_json, join(dir, d.flights_csv)};
  for (const auto& [k, f] : d.glider_files) out.push_back(join(dir, f));
  return out;
}

Dataset load_dataset(const std::string& path) {
  Dataset d;
  const std::string dir = directory_of(path);
  json j;
  try {
    j = parse_json(read_file(path), "the dataset file");
  } catch (const InputError& e) {
    const std::string m = e.what();
    throw InputError(m.rfind("cannot read", 0) == 0 ? m : path + ": " + m);
  }
  auto fail = [&](const std::string& m) { throw InputError(path + ": " + m); };
  if (!j.is_object()) fail("a dataset file must hold a JSON object");
  if (!j.contains("format") || !j["format"].is_string() || j["format"] != "pteromys-flights/1")
    fail("unknown format " + (j.contains("format") ? j["format"].dump() : std::string("(missing)")) +
         " (expected \"pteromys-flights/1\")");
  auto num = [&](const char* k, double def, const json& obj, const std::string& pre) {
    if (!obj.contains(k)) {
      d.defaulted.push_back(pre + k);
      return def;
    }
    const json& v = obj.at(k);
    if (!v.is_number()) fail(pre + k + " must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x <= 0) fail(pre + k + " must be a positive number");
    return x;
  };
  if (!j.contains("gliders") || !j["gliders"].is_object() || j["gliders"].empty())
    fail("missing key 'gliders' (an object: key -> glider file)");
  for (const auto& [k, v] : j["gliders"].items()) {
    if (!v.is_string()) fail("gliders." + k + " must be a file path");
    d.glider_files[k] = v.get<std::string>();
    d.gliders[k] = load_glider(join(dir, v.get<std::string>()));
  }
  if (!j.contains("flights_csv") || !j["flights_csv"].is_string()) fail("missing key 'flights_csv'");
  d.flights_csv = j["flights_csv"].get<std::string>();
  d.frame_rate_hz = num("frame_rate_hz", 30.0, j, "");
  d.tracking_sigma_m = num("tracking_sigma_m", 0.05, j, "");
  if (j.contains("air") && !j["air"].is_object()) fail("air must be an object");
  const json air = j.contains("air") ? j["air"] : json::object();  // left out: both defaulted
  d.air_density = num("density_kg_m3", 1.2, air, "air.");
  d.air_viscosity = num("viscosity_pa_s", 1.8e-5, air, "air.");
  d.gravity = num("gravity_m_s2", 9.81, j, "");

  const std::string csv_path = join(dir, d.flights_csv);
  const std::string csv_text = read_file(csv_path);
  // Names go into JSON results and reports, which hold UTF-8 only: a file
  // saved in another encoding (Latin-1 from a spreadsheet) is named here,
  // not after the whole fit.
  if (const auto bad = first_invalid_utf8(csv_text); bad != std::string::npos) {
    const long ln = 1 + std::count(csv_text.begin(), csv_text.begin() + bad, '\n');
    throw InputError(csv_path + " line " + std::to_string(ln) + ": byte 0x" +
                     hex_byte(static_cast<unsigned char>(csv_text[bad])) +
                     " is not UTF-8 text; save the file as UTF-8");
  }
  std::stringstream csv(csv_text);
  std::string line;
  long lineno = 0;
  auto where = [&](long ln) { return csv_path + " line " + std::to_string(ln); };
  std::vector<std::string> header;
  while (std::getline(csv, line)) {
    ++lineno;
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark (spreadsheets)
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    header = split_csv_line(line);
    break;
  }
  const std::vector<std::string> need{"flight", "glider", "t_s", "x_m", "y_m"};
  if (header.size() < 5 || !std::equal(need.begin(), need.end(), header.begin()))
    throw InputError(where(lineno) + ": header must start with flight,glider,t_s,x_m,y_m");
  d.extra_columns.assign(header.begin() + 5, header.end());
  std::map<std::string, std::size_t> index;
  std::string last;
  while (std::getline(csv, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const auto cells = split_csv_line(line);
    if (cells.size() < 5) throw InputError(where(lineno) + ": expected at least 5 columns");
    if (cells.size() > header.size()) throw InputError(where(lineno) + ": more columns than the header");
    const std::string& name = cells[0];
    if (name.empty()) throw InputError(where(lineno) + ": empty flight name");
    if (!d.gliders.count(cells[1]))
      throw InputError(where(lineno) + ": unknown glider key '" + cells[1] + "' (dataset.json lists " +
                       std::to_string(d.gliders.size()) + " gliders)");
    auto it = index.find(name);
    if (it == index.end()) {
      index[name] = d.flights.size();
      TrackedFlight f;
      f.name = name;
      f.glider = cells[1];
      for (std::size_t c = 5; c < cells.size(); ++c)
        if (!cells[c].empty()) f.extra[header[c]] = cells[c];
      d.flights.push_back(std::move(f));
      it = index.find(name);
    } else if (last != name) {
      throw InputError(where(lineno) + ": rows of flight '" + name + "' are not together");
    }
    TrackedFlight& f = d.flights[it->second];
    if (f.glider != cells[1])
      throw InputError(where(lineno) + ": flight '" + name + "' changes glider from '" + f.glider + "' to '" + cells[1] + "'");
    TrackedPoint p{parse_decimal(cells[2], where(lineno) + " t_s"), parse_decimal(cells[3], where(lineno) + " x_m"),
                   parse_decimal(cells[4], where(lineno) + " y_m")};
    if (!f.points.empty() && !(p.t > f.points.back().t))
      throw InputError(where(lineno) + ": time does not increase in flight '" + name + "'");
    f.points.push_back(p);
    last = name;
  }
  auto problems = dataset_problems(d);
  if (!problems.empty()) throw InputError(path + ": " + problems.front());
  return d;
}

void save_dataset(const Dataset& d, const std::string& dir) {
  auto problems = dataset_problems(d);
  for (const auto& [k, f] : d.glider_files)
    if (!d.gliders.count(k)) problems.push_back("glider file given for unknown key '" + k + "'");
  if (!problems.empty()) throw InputError("cannot write the dataset: " + problems.front());
  make_dirs(dir);
  json gl = json::object();
  for (const auto& [k, g] : d.gliders) {
    auto it = d.glider_files.find(k);
    const std::string rel = it != d.glider_files.end() ? it->second : "gliders/" + k + ".glider.json";
    gl[k] = rel;
    make_dirs(directory_of(join(dir, rel)));
    save_glider(g, join(dir, rel));
  }
  std::ostringstream csv;
  csv.precision(10);
  csv << "flight,glider,t_s,x_m,y_m";
  for (const auto& c : d.extra_columns) csv << "," << c;
  csv << "\n";
  for (const auto& f : d.flights)
    for (std::size_t i = 0; i < f.points.size(); ++i) {
      const auto& p = f.points[i];
      csv << f.name << "," << f.glider << "," << p.t << "," << p.x << "," << p.y;
      for (const auto& c : d.extra_columns) {
        auto e = f.extra.find(c);
        csv << "," << (e == f.extra.end() ? "" : e->second);
      }
      csv << "\n";
    }
  write_file_atomic(join(dir, d.flights_csv), csv.str());
  json j = {{"format", "pteromys-flights/1"},
            {"gliders", gl},
            {"flights_csv", d.flights_csv},
            {"frame_rate_hz", d.frame_rate_hz},
            {"tracking_sigma_m", d.tracking_sigma_m},
            {"air", {{"density_kg_m3", d.air_density}, {"viscosity_pa_s", d.air_viscosity}}},
            {"gravity_m_s2", d.gravity}};
  write_file_atomic(join(dir, "dataset.json"), j.dump(2) + "\n");
}

std::vector<const TrackedFlight*> flights_of(const Dataset& d, const std::string& key) {
  std::vector<const TrackedFlight*> out;
  for (const auto& f : d.flights)
    if (f.glider == key) out.push_back(&f);
  return out;
}

}  // namespace pteromys
