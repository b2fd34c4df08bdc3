// Flight datasets: dataset.json beside flights.csv (spec/formats.md, "Flight dataset").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "pteromys/glider.hpp"

namespace pteromys {

/// One tracked centre-of-gravity position (world frame, flight plane).
struct TrackedPoint {
  double t = 0;  ///< s, from any origin per flight
  double x = 0;  ///< m, horizontal along the flight
  double y = 0;  ///< m, up
};

struct TrackedFlight {
  std::string name;    ///< unique flight name
  std::string glider;  ///< key of Dataset::gliders
  std::vector<TrackedPoint> points;  ///< time order, strictly increasing t
  /// Optional per-flight columns (for example launcher_speed_m_s), taken from
  /// the flight's first row; empty cells are left out.
  std::map<std::string, std::string> extra;
};

struct Dataset {
  std::map<std::string, std::string> glider_files;  ///< key -> path relative to dataset.json
  std::map<std::string, Glider> gliders;            ///< key -> glider (loaded, validated)
  std::string flights_csv = "flights.csv";
  double frame_rate_hz = 30.0;
  double tracking_sigma_m = 0.05;
  double air_density = 1.2;
  double air_viscosity = 1.8e-5;
  double gravity = 9.81;
  std::vector<TrackedFlight> flights;
  /// Column names of the optional per-flight columns, in file order.
  std::vector<std::string> extra_columns;
  /// Keys dataset.json did not give, whose defaults above were taken
  /// (frame_rate_hz, tracking_sigma_m, air.density_kg_m3,
  /// air.viscosity_pa_s, gravity_m_s2), for commands to say so.
  std::vector<std::string> defaulted;
};

/// Reads dataset.json and what it refers to. Throws InputError naming the
/// file, line and problem: unknown format, missing key, glider file missing
/// or invalid, unknown glider key, wrong CSV header, fewer than 6 points in a
/// flight, time not increasing, NaN or non-numeric values, rows of a flight
/// not contiguous.
Dataset load_dataset(const std::string& dataset_json);

/// The files a dataset loaded from `dataset_json` was read from: that file,
/// its flights CSV and its glider files (paths as load_dataset opened them).
std::vector<std::string> dataset_files(const std::string& dataset_json, const Dataset& d);

/// Writes dir/dataset.json, dir/<flights_csv> and every glider to
/// dir/<glider_files[key]> (directories created). Each file is written
/// atomically. Checks the dataset first (same rules as loading).
void save_dataset(const Dataset& d, const std::string& dir);

/// The problems of a dataset in memory (empty when valid).
std::vector<std::string> dataset_problems(const Dataset& d);

/// Flights of one glider.
std::vector<const TrackedFlight*> flights_of(const Dataset& d, const std::string& glider_key);

}  // namespace pteromys
