// Fuzz target: coefficient model files (pteromys-model/1, flat plate or RBF).
// Oracle: an accepted model evaluates to finite coefficients over the angles
// a flight uses and writes back to a model that reads again.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "pteromys/coefficients.hpp"
#include "pteromys/io.hpp"

using namespace pteromys;
using pteromys_fuzz::accepts;
using pteromys_fuzz::fuzz_abort;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::shared_ptr<const CoefficientModel> m;
  if (!accepts([&] { m = model_from_json(parse_json(text, "the model file")); })) return 0;
  if (!m) fuzz_abort("the model reader accepted a file but returned no model");
  for (double a : {-3.0, -1.0, -0.2, 0.0, 0.1, 0.5, 1.5, 3.1}) {
    for (double xi : {-0.8, 0.0, 0.8}) {
      const Coefficients c = m->eval({a, 5e4, xi, -xi});
      if (!std::isfinite(c.cd) || !std::isfinite(c.cl) || !std::isfinite(c.cm))
        fuzz_abort("an accepted model gives a non-finite coefficient");
    }
  }
  const std::string again = model_to_json(*m).dump();
  if (!accepts([&] { (void)model_from_json(parse_json(again, "the model file")); }))
    fuzz_abort("a model the reader accepted does not read back after writing");
  return 0;
}
