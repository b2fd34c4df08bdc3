#include "pteromys/dataset.hpp"

#include <cstdio>
#include <fstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

std::string temp_dir() {
  char tmpl[] = "/tmp/pteromys-ds-XXXXXX";
  return mkdtemp(tmpl);
}

Dataset small_dataset() {
  Dataset d;
  d.gliders["g01"] = test::examples().front().second;
  d.glider_files["g01"] = "gliders/g01.glider.json";
  for (int k = 0; k < 2; ++k) {
    TrackedFlight f;
    f.name = "f" + std::to_string(k);
    f.glider = "g01";
    f.extra["launcher_speed_m_s"] = "7.5";
    for (int i = 0; i < 8; ++i) f.points.push_back({i / 30.0, 0.2 * i, 1.5 - 0.01 * i * i});
    d.flights.push_back(f);
  }
  d.extra_columns = {"launcher_speed_m_s"};
  return d;
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace

TEST(Dataset, RoundTrip) {
  const std::string dir = temp_dir();
  const Dataset d = small_dataset();
  save_dataset(d, dir);
  const Dataset e = load_dataset(dir + "/dataset.json");
  ASSERT_EQ(e.flights.size(), 2u);
  EXPECT_EQ(e.flights[1].name, "f1");
  ASSERT_EQ(e.flights[1].points.size(), 8u);
  EXPECT_NEAR(e.flights[1].points[7].y, d.flights[1].points[7].y, 1e-12);
  EXPECT_EQ(e.flights[0].extra.at("launcher_speed_m_s"), "7.5");
  EXPECT_EQ(e.gliders.at("g01").wings.size(), d.gliders.at("g01").wings.size());
  EXPECT_EQ(flights_of(e, "g01").size(), 2u);
}

// Each broken dataset is refused with its own reason.
TEST(Dataset, BrokenDatasetsAreRejectedWithReasons) {
  const std::string dir = temp_dir();
  save_dataset(small_dataset(), dir);
  const std::string good_csv = read_file(dir + "/flights.csv");
  const std::string good_json = read_file(dir + "/dataset.json");
  struct Case {
    std::string csv, json, fragment;
  };
  std::string few = "flight,glider,t_s,x_m,y_m\n";
  for (int i = 0; i < 5; ++i) few += "a,g01," + std::to_string(i * 0.1) + ",0,1\n";
  const std::vector<Case> cases{
      {"flight,glider,t_s,x_m,y_m\na,g99,0,0,1\n", good_json, "unknown glider key 'g99'"},
      {few, good_json, "at least 6"},
      {"flight,glider,t_s,x_m,y_m\na,g01,0,0,1\na,g01,0.1,0,1\na,g01,0.1,0,1\n", good_json, "time does not increase"},
      {"flight,glider,t_s,x_m,y_m\na,g01,0,nan,1\n", good_json, "NaN"},
      {"flight,glider,t_s,x_m,y_m\na,g01,0,abc,1\n", good_json, "not a number"},
      {"time,x,y\n1,2,3\n", good_json, "header"},
      {good_csv, R"({"format": "pteromys-flights/2"})", "unknown format"},
      {good_csv, R"({"format": "pteromys-flights/1", "flights_csv": "flights.csv"})", "missing key 'gliders'"},
      {good_csv, R"({"format": "pteromys-flights/1", "gliders": {"g01": "nowhere.glider.json"}, "flights_csv": "flights.csv"})",
       "no such file"},
  };
  for (const auto& c : cases) {
    write(dir + "/flights.csv", c.csv);
    write(dir + "/dataset.json", c.json);
    try {
      load_dataset(dir + "/dataset.json");
      ADD_FAILURE() << "accepted: " << c.fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.fragment), std::string::npos) << e.what();
    }
  }
}

TEST(Dataset, NonContiguousRowsAreRejected) {
  const std::string dir = temp_dir();
  save_dataset(small_dataset(), dir);
  std::string csv = "flight,glider,t_s,x_m,y_m\n";
  for (int i = 0; i < 6; ++i) csv += "a,g01," + std::to_string(i) + ",0,1\n";
  for (int i = 0; i < 6; ++i) csv += "b,g01," + std::to_string(i) + ",0,1\n";
  csv += "a,g01,10,0,1\n";
  write(dir + "/flights.csv", csv);
  EXPECT_THROW(load_dataset(dir + "/dataset.json"), InputError);
}

// Values in the wrong units are refused by their limits (docs/formats.md):
// each limit itself is accepted, a little past it is not, and the message
// names the unit.
TEST(Dataset, ValuesInTheWrongUnitsAreRefusedAtTheirLimits) {
  auto problems_with = [](auto change) {
    Dataset d = small_dataset();
    change(d);
    return dataset_problems(d);
  };
  auto first_has = [](const std::vector<std::string>& p, const std::string& fragment) {
    return !p.empty() && p.front().find(fragment) != std::string::npos;
  };
  // a flight of 6 points 12 s apart spans 60 s: gaps are the message, not the span
  auto spaced = [](double dt) {
    return [dt](Dataset& d) {
      for (std::size_t i = 0; i < d.flights[0].points.size(); ++i) d.flights[0].points[i].t = dt * i;
    };
  };
  EXPECT_TRUE(problems_with(spaced(2.0)).empty());  // 8 points 2 s apart: 14 s, gaps at the limit
  EXPECT_TRUE(first_has(problems_with(spaced(2.01)), "has no point for 2.01 s (t = 0 to 2.01 s)"));
  EXPECT_TRUE(first_has(problems_with(spaced(8.0)), "has no point for 8 s"));  // a 56 s span, its gaps over 2 s
  const auto ms = problems_with(spaced(60.01 / 7));
  EXPECT_TRUE(first_has(ms, "spans 60.01 s from its first to its last point: times are in seconds")) << ms.front();
  EXPECT_EQ(ms.size(), 1u);  // one message for the flight, the span's
  auto at = [](double x, double y) {
    return [x, y](Dataset& d) { d.flights[1].points[3] = {d.flights[1].points[3].t, x, y}; };
  };
  EXPECT_TRUE(problems_with(at(10000.0, -10000.0)).empty());
  EXPECT_TRUE(first_has(problems_with(at(10000.5, 1.0)), "flight 'f1' point 3 is at (10000.5, 1) m: positions are in metres"));
  EXPECT_TRUE(first_has(problems_with(at(0.0, -1e30)), "is at (0, -1e+30) m"));
  EXPECT_TRUE(problems_with([](Dataset& d) { d.tracking_sigma_m = 10.0; }).empty());
  EXPECT_TRUE(first_has(problems_with([](Dataset& d) { d.tracking_sigma_m = 12.0; }), "tracking_sigma_m is 12 m"));
}

// A byte order mark before the CSV header is skipped; keys left out are
// listed as defaulted.
TEST(Dataset, ByteOrderMarkIsSkippedAndDefaultsAreListed) {
  const std::string dir = temp_dir();
  save_dataset(small_dataset(), dir);
  write(dir + "/flights.csv", "\xEF\xBB\xBF" + read_file(dir + "/flights.csv"));
  auto j = parse_json(read_file(dir + "/dataset.json"), "dataset");
  j.erase("tracking_sigma_m");
  j.erase("air");
  write(dir + "/dataset.json", j.dump());
  const Dataset e = load_dataset(dir + "/dataset.json");
  EXPECT_EQ(e.flights.size(), 2u);
  EXPECT_EQ(e.tracking_sigma_m, 0.05);
  EXPECT_EQ(e.defaulted, (std::vector<std::string>{"tracking_sigma_m", "air.density_kg_m3", "air.viscosity_pa_s"}));
}
