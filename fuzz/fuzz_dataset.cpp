// Fuzz target: flight datasets (pteromys-flights/1: dataset.json beside
// flights.csv). The first byte chooses which file the rest of the input
// becomes; the other file is a valid one. Oracle: an accepted dataset has no
// problems by the writer's rules and saves.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_support.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/io.hpp"

using namespace pteromys;
using pteromys_fuzz::accepts;
using pteromys_fuzz::fuzz_abort;
namespace fs = std::filesystem;

namespace {

const char* kGlider = R"({"format": "pteromys-glider/1", "name": "g",
 "material": {"thickness_m": 0.003, "density_kg_m3": 30},
 "fuselage": {"outline_m": [[0, 0], [-0.3, 0.01], [-0.3, 0.04], [-0.28, 0.04], [-0.25, 0.012], [0, 0.012]]},
 "wings": [{"name": "main", "outline_m": [[-0.05, 0], [-0.07, 0.2], [-0.12, 0.2], [-0.12, -0.2], [-0.07, -0.2]],
            "mount": {"x_m": 0, "y_m": 0.012, "angle_deg": 2}},
           {"name": "tail", "outline_m": [[-0.25, 0], [-0.27, 0.06], [-0.3, 0.06], [-0.3, -0.06], [-0.27, -0.06]],
            "mount": {"x_m": 0, "y_m": 0.012, "angle_deg": 0}}],
 "ballast": [{"name": "clip", "mass_kg": 0.002, "x_m": -0.01, "y_m": 0.005}]})";
const char* kDataset = R"({"format": "pteromys-flights/1", "gliders": {"g": "g.glider.json"},
 "flights_csv": "flights.csv", "frame_rate_hz": 30, "tracking_sigma_m": 0.01})";
const char* kCsv =
    "flight,glider,t_s,x_m,y_m\n"
    "f1,g,0,0,1.5\nf1,g,0.033,0.2,1.52\nf1,g,0.067,0.4,1.53\nf1,g,0.1,0.6,1.53\n"
    "f1,g,0.133,0.8,1.52\nf1,g,0.167,1.0,1.5\nf1,g,0.2,1.2,1.47\n";

const fs::path& workdir() {
  static const fs::path d = [] {
    fs::path p = fs::temp_directory_path() / ("pteromys-fuzz-dataset-" + std::to_string(::getpid()));
    fs::create_directories(p);
    std::ofstream(p / "g.glider.json") << kGlider;
    return p;
  }();
  return d;
}

void put(const fs::path& p, const std::string& s) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const fs::path& d = workdir();
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const bool csv = (data[0] & 1) == 0;
  put(d / "dataset.json", csv ? std::string(kDataset) : rest);
  put(d / "flights.csv", csv ? rest : std::string(kCsv));
  Dataset ds;
  if (!accepts([&] { ds = load_dataset((d / "dataset.json").string()); })) return 0;
  const auto problems = dataset_problems(ds);
  if (!problems.empty()) fuzz_abort("an accepted dataset has problems: " + problems.front());
  accepts([&] { save_dataset(ds, (d / "saved").string()); });
  return 0;
}
