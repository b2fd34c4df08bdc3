// Helpers shared by the subcommands: loading a glider with the model and
// options every aerodynamic command takes.
#pragma once

#include <memory>
#include <string>
#include <vector>

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

/// A named path of a command: what it is ("the model", "--json") and where.
struct NamedPath {
  std::string what, path;
};

/// Refuses, before long work starts, an output that is one of the inputs
/// (`fit DATA/dataset.json -o DATA/dataset.json` would replace the dataset)
/// or the same file as another output (`-o X --json X` would keep only the
/// last). Files are compared by identity where they exist (links and
/// different spellings of a path included) and by their resolved path where
/// they do not yet; devices and pipes (/dev/null, /dev/stdout) are exempt.
void check_distinct_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

/// Where a write to `path` lands, spelt one way: its links followed
/// (output_target, or the path as given where that refuses it) and its
/// directory resolved (realpath, when it exists).
std::string resolved_path(const std::string& path);

/// check_distinct_outputs for a command on one glider (load_setup's inputs:
/// the glider file and --model) writing the given (what, option) outputs
/// that the command line has.
void check_setup_outputs(const Args& a, const std::vector<NamedPath>& output_options);

/// Whether `p` exists (links followed); is a directory; is a regular file.
bool exists(const std::string& p);
bool is_dir(const std::string& p);
bool is_file(const std::string& p);

/// `p` without trailing slashes ("rep/" names the directory rep; "/" stays).
std::string strip_slash(std::string p);

}  // namespace pteromys::cli
