// Fuzz target: glider files (pteromys-glider/1). Oracle: whatever the reader
// accepts must write back and read again to the same glider, and its mass
// properties must be finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "pteromys/glider.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"

using namespace pteromys;
using pteromys_fuzz::accepts;
using pteromys_fuzz::fuzz_abort;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Glider g;
  // As load_glider reads a file: parse, then validate.
  if (!accepts([&] {
        g = glider_from_json_text(text);
        validate(g);
      }))
    return 0;
  const std::string again = glider_to_json(g).dump();
  Glider g2;
  if (!accepts([&] {
        g2 = glider_from_json_text(again);
        validate(g2);
      }))
    fuzz_abort("a glider the reader accepted does not read back after writing");
  if (glider_to_json(g2).dump() != again) fuzz_abort("write -> read -> write is not stable");
  const MassProperties m = mass_properties(g);
  if (!std::isfinite(m.mass) || !(m.mass > 0) || !std::isfinite(m.inertia) || !std::isfinite(m.cg.x)) fuzz_abort("accepted glider has a non-finite or zero mass");
  return 0;
}
