// Minimal command-line argument parsing for the pteromys subcommands.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "pteromys/types.hpp"

namespace pteromys::cli {

/// Parsed arguments: positionals in order, options by name ("--json" -> value),
/// flags by name. Unknown options are an error naming them.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;
  std::set<std::string> flags;

  bool has(const std::string& k) const { return options.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def = "") const {
    auto it = options.find(k);
    return it == options.end() ? def : it->second;
  }
  double number(const std::string& k, double def) const;
  /// The option as an int if it is a whole number in [lo, hi] (`def` when
  /// absent); otherwise InputError "KEY must be a whole number between LO and HI".
  int whole(const std::string& k, int def, int lo, int hi) const;
  bool flag(const std::string& k) const { return flags.count(k) > 0; }
};

/// `valued`: options that take a value; `bare`: flags without value.
Args parse_args(const std::vector<std::string>& argv, const std::set<std::string>& valued,
                const std::set<std::string>& bare);

}  // namespace pteromys::cli
