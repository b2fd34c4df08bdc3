// Helpers shared by the subcommands: loading a glider with the model and
// options every aerodynamic command takes.
#pragma once

#include <memory>
#include <string>

#include "args.hpp"
#include "pteromys/analysis.hpp"
#include "pteromys/io.hpp"

namespace pteromys::cli {

/// Options every command that uses aerodynamics takes.
extern const char* kAeroOptionsHelp;
std::set<std::string> aero_valued_options();

struct Setup {
  Glider glider;
  std::shared_ptr<const CoefficientModel> model;
  AeroOptions aero;
  AnalysisOptions analysis;
  Environment env;
};

/// Loads GLIDER (first positional) and the aerodynamic options.
Setup load_setup(const Args& a);

/// One-paragraph human summary of a flyability report.
std::string summary_text(const Flyability& f);

/// Checks that an output path can be written before long work starts.
void check_writable(const std::string& path, const std::string& what);

/// Whether `p` exists (links followed); is a directory; is a regular file.
bool exists(const std::string& p);
bool is_dir(const std::string& p);
bool is_file(const std::string& p);

/// `p` without trailing slashes ("rep/" names the directory rep; "/" stays).
std::string strip_slash(std::string p);

}  // namespace pteromys::cli
