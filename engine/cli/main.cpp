// The pteromys command: dispatches to subcommands; one-line errors on stderr.
#include <algorithm>
#include <exception>
#include <iostream>

#include "commands.hpp"
#include "pteromys/io.hpp"
#include "pteromys/types.hpp"
#include "pteromys/version.hpp"

namespace pteromys::cli {
std::vector<Command>& registry() {
  static std::vector<Command> r;
  return r;
}
bool register_command(int order, Command c) {
  c.order = order;
  auto& r = registry();
  r.insert(std::upper_bound(r.begin(), r.end(), c, [](const Command& a, const Command& b) { return a.order < b.order; }), std::move(c));
  return true;
}
}  // namespace pteromys::cli

namespace {
void print_help() {
  std::cout << "usage: pteromys COMMAND [ARGS]\n\n"
               "Design, optimise and build hand-launched free-flight gliders made of flat plates.\n\n"
               "commands:\n";
  for (const auto& c : pteromys::cli::registry())
    std::cout << "  " << c.name << std::string(c.name.size() < 10 ? 10 - c.name.size() : 1, ' ') << c.summary << "\n";
  std::cout << "\nEach command takes --help. Version " << pteromys::kVersion << ".\n";
}
}  // namespace

int main(int argc, char** argv) {
  using namespace pteromys::cli;
  std::vector<std::string> args(argv + 1, argv + argc);
  pteromys::remove_temp_files_on_signal();
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    print_help();
    if (!args.empty()) return 0;
    std::cerr << "pteromys: error: no command given (usage above; see pteromys --help)\n";
    return 2;
  }
  if (args[0] == "--version") {
    std::cout << "pteromys " << pteromys::kVersion << "\n";
    return 0;
  }
  for (const auto& c : registry()) {
    if (c.name != args[0]) continue;
    std::vector<std::string> rest(args.begin() + 1, args.end());
    for (const auto& r : rest)
      if (r == "--help" || r == "-h") {
        std::cout << c.help;
        return 0;
      }
    try {
      return c.run(rest);
    } catch (const pteromys::InputError& e) {
      std::cerr << "pteromys " << c.name << ": error: " << e.what() << "\n";
      return 2;
    } catch (const std::bad_alloc&) {
      std::cerr << "pteromys " << c.name << ": error: out of memory\n";
      return 3;
    } catch (const std::exception& e) {
      std::cerr << "pteromys " << c.name << ": internal error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "pteromys: error: unknown command '" << args[0] << "' (see pteromys --help)\n";
  return 2;
}
