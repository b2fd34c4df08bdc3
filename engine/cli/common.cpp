#include "common.hpp"

#include "pteromys/io.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace pteromys::cli {

const char* kAeroOptionsHelp =
    "  --model MODEL.json   aerodynamic coefficient model (default: the shipped model)\n"
    "  --height M           launch height of the standard launches [m] (default 1.5)\n"
    "  --dz M               spacing of the wing-element cut lines [m] (default 0.005)\n"
    "  --dt S               simulation time step [s] (default 0.002)\n"
    "  --integrator NAME    verlet (default, as in the paper) or rk4\n";

std::set<std::string> aero_valued_options() {
  return {"--model", "--height", "--dz", "--dt", "--integrator"};
}

Setup load_setup(const Args& a) {
  if (a.positional.empty()) throw InputError("missing GLIDER file (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  Setup s;
  s.glider = load_glider(a.positional[0]);
  s.model = a.has("--model") ? load_model(a.get("--model")) : default_model();
  s.aero.dz = a.number("--dz", s.aero.dz);
  if (!(s.aero.dz > 0) || s.aero.dz > 0.1) throw InputError("--dz must be in (0, 0.1] m");
  s.analysis.launch_height = a.number("--height", 1.5);
  if (!(s.analysis.launch_height >= 0) || s.analysis.launch_height > 100)
    throw InputError("--height must be between 0 and 100 m");
  s.analysis.sim.dt = a.number("--dt", s.analysis.sim.dt);
  check_time_step(s.analysis.sim.dt, "--dt");
  const std::string integ = a.get("--integrator", "verlet");
  if (integ == "verlet") s.analysis.sim.integrator = Integrator::Verlet;
  else if (integ == "rk4") s.analysis.sim.integrator = Integrator::RK4;
  else throw InputError("--integrator must be verlet or rk4, got '" + integ + "'");
  return s;
}

std::string summary_text(const Flyability& f) {
  std::ostringstream s;
  s.precision(3);
  s << "mass " << f.mass.mass * 1000 << " g, CG (" << f.mass.cg.x << ", " << f.mass.cg.y << ") m\n";
  s << (f.flyable ? "flyable" : "NOT flyable") << "\n";
  for (const auto& r : f.reasons) s << "  - " << r << "\n";
  if (f.glide.exists)
    s << "steady glide: " << f.glide.speed << " m/s at alpha " << rad2deg(f.glide.gamma)
      << " deg, glide ratio " << f.glide.ratio << ", static margin " << f.static_margin * 100 << " %\n";
  for (const auto& l : f.launches)
    s << "  launch " << l.launch.speed << " m/s, " << l.launch.climb_deg << " deg up: "
      << l.flight.distance << " m in " << l.flight.flight_time << " s"
      << (l.flight.stable ? "" : " (unstable)") << "\n";
  for (const auto& w : f.warnings) s << "warning: " << w << "\n";
  return s.str();
}

void check_writable(const std::string& path, const std::string& what) {
  if (path.empty()) throw InputError("cannot write " + what + ": no file name given (an empty path)");
  if (own_descriptor(path) >= 0) return;  // /dev/stdout: written into, wherever it goes
  struct stat st {};
  if (stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw InputError("cannot write " + what + " '" + path + "': it is a directory");
    if (!S_ISREG(st.st_mode)) {
      // a device or pipe (/dev/stdout, /dev/null) is written into
      if (access(path.c_str(), W_OK) != 0)
        throw InputError("cannot write " + what + " '" + path + "': permission denied");
      return;
    }
  }
  // a symbolic link is written through: its target's directory must take
  // the new file
  const std::string target = output_target(path);  // (a loop of links: its own message)
  const std::string dir = directory_of(target);
  // a symbolic link's target is where the file goes: say so
  const std::string via = target == path ? std::string() : " (where the symbolic link points: '" + target + "')";
  if (stat(dir.c_str(), &st) != 0)
    throw InputError("cannot write " + what + " '" + path + "': directory '" + dir + "' " +
                     (errno == EACCES ? "cannot be reached (permission denied)" : "does not exist") + via);
  if (!S_ISDIR(st.st_mode))
    throw InputError("cannot write " + what + " '" + path + "': '" + dir + "' is not a directory" + via);
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError("cannot write " + what + " '" + path + "': directory '" + dir + "' is not writable" + via);
}

namespace {
/// Identity of a path for check_distinct_outputs: "" for a device, pipe or
/// socket; else the device and inode of an existing file or directory, or the
/// resolved directory and name of one that does not exist yet.
std::string path_identity(const std::string& path) {
  // /dev/stdout and the like are written into in place, one after another,
  // whatever file the shell redirected them to
  if (own_descriptor(path) >= 0) return "";
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (!S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) return "";
    return "i" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  }
  return "p" + resolved_path(path);
}
}  // namespace

std::string resolved_path(const std::string& path) {
  std::string target = path;
  try {
    target = output_target(path);
  } catch (const InputError&) {  // a directory, a device, a loop of links: the path as given
  }
  const std::string dir = directory_of(target);
  char* real = ::realpath(dir.c_str(), nullptr);
  const std::string r = real ? std::string(real) : dir;
  std::free(real);
  return r + "/" + file_name(target);
}

void check_distinct_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  std::vector<std::string> ids;
  for (const auto& o : outputs) ids.push_back(o.path.empty() ? "" : path_identity(o.path));
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (ids[i].empty()) continue;
    for (const auto& in : inputs)
      if (!in.path.empty() && path_identity(in.path) == ids[i])
        throw InputError("cannot write " + outputs[i].what + " '" + outputs[i].path + "': it is " + in.what + " '" +
                         in.path + "', which the command reads; write it elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (ids[j] == ids[i])
        throw InputError("cannot write " + outputs[i].what + " '" + outputs[i].path + "': it is the same file as " +
                         outputs[j].what + " '" + outputs[j].path + "'; give each output its own file");
  }
}

void check_setup_outputs(const Args& a, const std::vector<NamedPath>& output_options) {
  std::vector<NamedPath> in, out;
  if (!a.positional.empty()) in.push_back({"the glider", a.positional[0]});
  if (a.has("--model")) in.push_back({"the model", a.get("--model")});
  for (const auto& o : output_options)
    if (a.has(o.path)) out.push_back({o.what + " (" + o.path + ")", a.get(o.path)});
  check_distinct_outputs(out, in);
}

bool exists(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0;
}

bool is_dir(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool is_file(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string strip_slash(std::string p) {
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  return p;
}

}  // namespace pteromys::cli
