// Files: glider, coefficient model, report, trajectories (spec/formats.md).
// Only this layer and the command line touch the file system.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pteromys/analysis.hpp"
#include "pteromys/coefficients.hpp"
#include "pteromys/glider.hpp"

namespace pteromys {

/// Parses a glider from JSON text (format "pteromys-glider/1"). Throws
/// InputError naming the problem: malformed JSON, unknown format, missing key,
/// wrong type, NaN or infinite number. Does not check geometry (see validate).
Glider glider_from_json_text(const std::string& text);
Glider glider_from_json(const nlohmann::json& j);
nlohmann::json glider_to_json(const Glider& g);

/// Reads and validates a glider file; messages start with the file name.
Glider load_glider(const std::string& path);
/// Writes a glider file atomically.
void save_glider(const Glider& g, const std::string& path);

/// Coefficient model files (format "pteromys-model/1", see docs/formats.md).
std::shared_ptr<const CoefficientModel> model_from_json(const nlohmann::json& j);
nlohmann::json model_to_json(const CoefficientModel& m);
std::shared_ptr<const CoefficientModel> load_model(const std::string& path);
void save_model(const CoefficientModel& m, const std::string& path);
/// The model shipped with the project (models/default.model.json, found
/// next to the executable, in the install prefix, or via PTEROMYS_MODEL).
/// Falls back to the built-in empirical flat-plate element when no file exists.
std::shared_ptr<const CoefficientModel> default_model();
/// Where default_model() found its file ("" for the built-in fallback).
std::string default_model_path();

/// Report in format "pteromys-report/1".
nlohmann::json report_to_json(const Flyability& f);

/// Trajectories CSV: header launch,t_s,x_m,y_m,pitch_deg,speed_m_s.
std::string trajectories_csv(const Flyability& f);

/// Writes text to `path` through a temporary file and a rename, so that a
/// failure (a full disk, a file size limit, a kill) leaves the old file or the
/// new one, never a fragment. Every write is checked, the data is flushed to
/// disk (fsync) before the rename. A symbolic link is written through (its
/// target replaced); an existing device, pipe or socket (/dev/null, a named
/// pipe) and an open file of this process (/dev/stdout, at its offset) are
/// written into, as a shell redirection would. Throws
/// InputError on failure (an empty path among them).
void write_file_atomic(const std::string& path, const std::string& text);

/// Writes several outputs of one command so that a failure leaves none of
/// them changed: every file target is written to its temporary file first,
/// then the in-place targets (a device, a pipe, /dev/stdout) are written, and
/// only then are the temporary files renamed into place. A failure before the
/// renames removes every temporary file and throws InputError naming the
/// output; the files are renamed in the order given.
void write_files_together(const std::vector<std::pair<std::string, std::string>>& files);

/// The open descriptor of this process that `path` names (/dev/stdout,
/// /dev/fd/N, /proc/self/fd/N, directly or through links), or -1.
/// write_file_atomic writes to it in place, as a shell redirection would.
int own_descriptor(const std::string& path);

/// Removes a temporary file from temp_path_for that will not be committed
/// (and forgets it for the signal handlers).
void discard_temp_file(const std::string& tmp);

/// Where a write to `path` lands: `path` with its symbolic links followed
/// (the file a link points to is replaced, the link stays). Throws
/// InputError naming `path` when it is empty, a directory, a device, pipe or
/// socket (which a rename would replace), one of this process's open files
/// (own_descriptor), or a loop of links.
std::string output_target(const std::string& path);

/// Why the directory `dir` may not be replaced by a diagnosis report
/// (pteromys diagnose --report, the FreeCAD command), or "" when it may: it
/// does not exist, is empty, or is an earlier report (index.html with only
/// what a report writes beside it: report.md, diagnosis.json, *.png).
/// Anything else in it (a person's files, the dataset itself) would be lost.
std::string report_dir_problem(const std::string& dir);

/// A fresh temporary name beside `path` (same directory, so that the rename is
/// atomic), ending in `suffix` (some writers choose the format by extension).
std::string temp_path_for(const std::string& path, const std::string& suffix = "");

/// Makes a temporary file that a library has written the output at `path`:
/// checks that it is complete (non-empty; ends with `trailer` when one is
/// given, ignoring trailing white space), flushes it to disk, renames it into
/// place and syncs the directory. On failure removes the temporary file and
/// throws InputError naming `path` (the old file, if any, is untouched).
void commit_temp_file(const std::string& tmp, const std::string& path, const std::string& trailer = "");

/// Renames a complete temporary file (from temp_path_for, already checked and
/// synced) into place; returns false when the rename fails. For writers that
/// commit several files together.
bool rename_temp_into_place(const std::string& tmp, const std::string& path);

/// The directory part of a path: "." for a bare name, "/" for a name at the
/// root (as dirname(1), without resolving links).
std::string directory_of(const std::string& path);

/// Offset of the first byte of `s` that is not part of well-formed UTF-8
/// (overlong forms, surrogates and code points above U+10FFFF count as
/// ill-formed), or std::string::npos when it all is.
std::size_t first_invalid_utf8(const std::string& s);

/// A byte as two upper-case hexadecimal digits (0xE9 -> "E9").
std::string hex_byte(unsigned char b);

/// `s` with every byte that is not well-formed UTF-8 written as "\xNN", for
/// messages that quote a user's text (Python turns a message into str).
std::string printable_utf8(const std::string& s);

/// The cells of one line of plain CSV (no quoted commas): each without its
/// surrounding white space (spaces, tabs, a Windows \r) and, if quoted,
/// without its quotes. A line ending in ',' has an empty last cell.
std::vector<std::string> split_csv_line(const std::string& line);

/// A cell as a message quotes it: in single quotes, at most 40 bytes, cut
/// between UTF-8 characters ("'999...'": a 5000-digit cell is named, not
/// echoed).
std::string quoted_cell(const std::string& cell);

/// A CSV cell as a decimal number, as a tracker or a spreadsheet writes it:
/// digits, a sign, a point and an exponent ("1.5E-3", "+2", ".5"). strtod
/// alone would also take hexadecimal ("0x1A" = 26), "inf" and "nan".
/// InputError "<where>: '<cell>' is not a number" (or "is not a decimal
/// number" for hexadecimal, "NaN or infinite value '<cell>'", "is beyond
/// the range of a number" for 1e999).
double parse_decimal(const std::string& cell, const std::string& where);

/// The last component of a path ("a/b.c" -> "b.c"; a bare name as it is).
std::string file_name(const std::string& path);

/// file_name up to its first dot ("clips/throw.2.avi" -> "throw"); a name
/// that starts with its only dot (".avi") is kept whole. May be empty.
std::string file_stem(const std::string& path);

/// `s` with every character other than an ASCII letter, a digit or one of
/// `keep` replaced by '_' (names that go into CSV cells and file names).
std::string safe_name(std::string s, const std::string& keep = "-_");

/// A glider's key in a dataset from its file's path: the file name without
/// `.glider.json` (or `.json`), with characters other than letters, digits,
/// '-', '_' and '.' as '_' (so it fits a CSV cell).
std::string glider_key_of(const std::string& path);

/// Records a temporary directory being filled (a report or a dataset written
/// beside its place and renamed into it), so that the signal handlers of
/// remove_temp_files_on_signal remove it with everything in it.
void register_temp_dir(const std::string& dir);

/// Removes a temporary directory from register_temp_dir with everything in
/// it, and forgets it.
void discard_temp_dir(const std::string& dir);

/// Forgets a temporary directory that has been renamed into place.
void forget_temp_dir(const std::string& dir);

/// Runs the program argv[0] (a path; no shell) with the environment `env`
/// ("NAME=value" each) and waits for it. Its standard output goes to the
/// descriptor `stdout_to` (1: unchanged), or with its standard error to
/// /dev/null when `stdout_to` is -2. It stays in this process's group (a
/// terminal's Ctrl-C, a SIGKILL to the group reach it too); the signal
/// handlers of remove_temp_files_on_signal kill it (SIGKILL; it must not
/// start children of its own that write there) before they remove the
/// temporary files and directories it may be writing. Returns its exit
/// status, 128 + the signal that ended it, or -1 when it could not be
/// started. For a single-threaded caller (the commands, when they render):
/// signals are held only in the calling thread while it is started, and a
/// handler run by another thread may reap it first.
int run_program(const std::vector<std::string>& argv, const std::vector<std::string>& env, int stdout_to = 1);

/// Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGQUIT that stop the
/// children of run_program, delete the temporary files of writes in progress
/// (from temp_path_for) and the temporary directories (register_temp_dir),
/// and then end the process as the signal would. (SIGKILL cannot be caught:
/// after it, the target is still the old file or the new one, and a
/// `*.tmp-PID-N` file or `*.tmp-PID` directory may remain beside it.)
void remove_temp_files_on_signal();
std::string read_file(const std::string& path);

/// An option value `v` as an int if it is a whole number in [lo, hi];
/// otherwise InputError "KEY must be a whole number between LO and HI". The
/// one check behind the commands' counts (Args::whole) and Python's keywords.
int whole_number(const std::string& key, double v, int lo, int hi);

/// Paths of the *.glider.json files directly in `dir`, sorted. Throws
/// InputError when the directory cannot be read.
std::vector<std::string> glider_files_in(const std::string& dir);

/// Parses JSON text; on failure throws InputError with line/column and, for
/// NaN/Infinity literals, says that they are not valid JSON numbers.
nlohmann::json parse_json(const std::string& text, const std::string& what);

/// A figure for a JSON report, or null where it was not computed (NaN,
/// infinite): JSON has no such numbers.
nlohmann::json num_or_null(double v);

}  // namespace pteromys
