#include "args.hpp"

#include <cmath>
#include <cstdlib>

#include "pteromys/io.hpp"

namespace pteromys::cli {

double Args::number(const std::string& k, double def) const {
  auto it = options.find(k);
  if (it == options.end()) return def;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(v))
    throw InputError("option " + k + " needs a number, got '" + it->second + "'");
  return v;
}

int Args::whole(const std::string& k, int def, int lo, int hi) const {
  return whole_number(k, number(k, def), lo, hi);
}

Args parse_args(const std::vector<std::string>& argv, const std::set<std::string>& valued,
                const std::set<std::string>& bare) {
  Args a;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& s = argv[i];
    if (s.size() > 1 && s[0] == '-' && !(s.size() > 1 && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.'))) {
      std::string key = s, val;
      const auto eq = s.find('=');
      const bool inline_val = eq != std::string::npos;
      if (inline_val) {
        key = s.substr(0, eq);
        val = s.substr(eq + 1);
      }
      if (valued.count(key)) {
        if (!inline_val) {
          if (i + 1 >= argv.size()) throw InputError("option " + key + " needs a value");
          val = argv[++i];
        }
        a.options[key] = val;
      } else if (bare.count(key) && !inline_val) {
        a.flags.insert(key);
      } else {
        throw InputError("unknown option " + key + " (see --help)");
      }
    } else {
      a.positional.push_back(s);
    }
  }
  return a;
}

}  // namespace pteromys::cli
