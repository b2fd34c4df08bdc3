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
