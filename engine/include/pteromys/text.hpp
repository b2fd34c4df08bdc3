// Small text helpers shared by the engine's messages and reports.
#pragma once

#include <sstream>
#include <string>

namespace pteromys {

/// A number for a sentence shown to a person: `precision` significant digits
/// (std::ostream default formatting), e.g. fmt_number(0.123456) == "0.123".
inline std::string fmt_number(double v, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace pteromys
