// The pteromys subcommands. Each returns the process exit code; errors in the
// input are thrown as InputError and reported on one line by main().
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace pteromys::cli {

struct Command {
  std::string name;
  int order = 0;        ///< position in `pteromys --help`
  std::string summary;  ///< one line for `pteromys --help`
  std::string help;     ///< full text for `pteromys NAME --help`
  std::function<int(const std::vector<std::string>&)> run;
};

/// Every registered subcommand, sorted by `order` for `pteromys --help`.
std::vector<Command>& registry();

/// Adds a command; used through a static initialiser in each commands_<area>.cpp:
///   static const bool reg = register_command(10, {...});
/// so that a new area needs no edit of a shared file.
bool register_command(int order, Command c);

}  // namespace pteromys::cli
