#include "pteromys/io.hpp"
#include "pteromys/text.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <mutex>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <cmath>
#include <dirent.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include "json_reader.hpp"

#ifndef PTEROMYS_SOURCE_DIR
#define PTEROMYS_SOURCE_DIR ""
#endif
#ifndef PTEROMYS_INSTALL_DATADIR
#define PTEROMYS_INSTALL_DATADIR ""
#endif

namespace pteromys {
using nlohmann::json;

using Reader = detail::JsonReader;

json num_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json parse_json(const std::string& text, const std::string& what) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    static const std::regex bad(R"((^|[^A-Za-z_"])(NaN|-?Infinity|nan|-?inf)([^A-Za-z_"]|$))");
    std::string msg = what + " is not valid JSON";
    if (std::regex_search(text, bad))
      msg += ": it contains NaN or Infinity, which are not numbers in JSON";
    else {
      std::string m = e.what();
      const auto p = m.find("syntax error");
      msg += " (" + (p == std::string::npos ? m : m.substr(p)) + ")";
    }
    throw InputError(msg);
  } catch (const json::out_of_range& e) {
    throw InputError(what + " holds a number that is not a finite number (too large for a double)");
  }
}

std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}

namespace {
/// Length of the well-formed UTF-8 sequence at s[i], or 0 (Unicode 15, table 3-7).
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}
}  // namespace

std::size_t first_invalid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    if (n == 0) return i;
    i += n;
  }
  return std::string::npos;
}

std::string hex_byte(unsigned char b) {
  static const char digits[] = "0123456789ABCDEF";
  return {digits[b >> 4], digits[b & 15]};
}

std::string printable_utf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    if (n == 0) {
      out += "\\x" + hex_byte(static_cast<unsigned char>(s[i]));
      ++i;
    } else {
      out.append(s, i, n);
      i += n;
    }
  }
  return out;
}

std::vector<std::string> split_csv_line(const std::string& line) {
  // Plain CSV as the spec uses it (no quoted commas in names); a cell's
  // surrounding white space (a spreadsheet's tab, a Windows \r) is not
  // part of it.
  std::vector<std::string> out;
  std::string cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    const auto isws = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!cell.empty() && isws(cell.back())) cell.pop_back();
    std::size_t b = 0;
    while (b < cell.size() && isws(cell[b])) ++b;
    cell = cell.substr(b);
    if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') cell = cell.substr(1, cell.size() - 2);
    out.push_back(cell);
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

std::string quoted_cell(const std::string& s) {
  if (s.size() <= 40) return "'" + s + "'";
  std::size_t n = 37;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;  // not inside a character
  return "'" + s.substr(0, n) + "...'";
}

double parse_decimal(const std::string& s, const std::string& where) {
  const bool decimal = !s.empty() && s.find_first_not_of("0123456789+-.eE") == std::string::npos;
  const auto body = s.find_first_not_of("+-");
  if (!decimal && body != std::string::npos && body <= 1) {
    std::string low;
    for (char c : s.substr(body)) low += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (low == "nan" || low == "inf" || low == "infinity")
      throw InputError(where + ": NaN or infinite value " + quoted_cell(s));
  }
  char* end = nullptr;
  const double v = decimal ? std::strtod(s.c_str(), &end) : 0.0;
  if (!decimal || end == s.c_str() || *end != '\0') {
    const bool hex = body != std::string::npos && s.size() > body + 1 && s[body] == '0' &&
                     (s[body + 1] == 'x' || s[body + 1] == 'X');
    throw InputError(where + ": " + quoted_cell(s) + (hex ? " is not a decimal number" : " is not a number"));
  }
  if (!std::isfinite(v)) throw InputError(where + ": " + quoted_cell(s) + " is beyond the range of a number");
  return v;
}

std::string file_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string file_stem(const std::string& path) {
  std::string b = file_name(path);
  const auto dot = b.find('.');
  if (dot != std::string::npos && dot > 0) b.resize(dot);
  return b;
}

std::string safe_name(std::string s, const std::string& keep) {
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || keep.find(c) != std::string::npos)) c = '_';
  return s;
}

std::string glider_key_of(const std::string& path) {
  std::string n = file_name(path);
  for (const std::string e : {".glider.json", ".json"})
    if (n.size() > e.size() && n.compare(n.size() - e.size(), e.size(), e) == 0) {
      n.resize(n.size() - e.size());
      break;
    }
  return safe_name(n, "-_.");
}

std::string read_file(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) throw InputError("cannot read '" + path + "': no such file");
  if (S_ISDIR(st.st_mode)) throw InputError("cannot read '" + path + "': it is a directory");
  // Every file read here (datasets, gliders, models, calibrations) is far
  // smaller; a device or a runaway file ("flights_csv": "/dev/zero") would
  // otherwise be read until memory runs out.
  constexpr std::size_t kMaxBytes = std::size_t(256) << 20;
  const auto too_large = [&] {
    return InputError("cannot read '" + path + "': it is larger than 256 MB, far more than any Pteromys input file");
  };
  if (S_ISREG(st.st_mode) && static_cast<unsigned long long>(st.st_size) > kMaxBytes) throw too_large();
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError("cannot read '" + path + "': permission denied or unreadable");
  std::string out;
  std::vector<char> buf(1 << 16);
  while (f) {
    f.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    out.append(buf.data(), static_cast<std::size_t>(f.gcount()));
    if (out.size() > kMaxBytes) throw too_large();
  }
  if (f.bad()) throw InputError("cannot read '" + path + "': a read error");
  return out;
}

namespace {

std::string errno_text(int e) {
  if (e == ENOSPC) return "the disk is full";
  if (e == EFBIG) return "the file size limit was reached";
  if (e == EDQUOT) return "the disk quota is exceeded";
  if (e == EACCES || e == EPERM) return "permission denied";
  if (e == ENOENT || e == ENOTDIR) return "the directory does not exist";
  if (e == EROFS) return "the file system is read-only";
  return std::strerror(e);
}

void fsync_dir_of(const std::string& path) {
  const int fd = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);  // best effort: some file systems refuse fsync on directories
    ::close(fd);
  }
}

// Temporary files being written and temporary directories being filled (a
// report, a generated dataset), for remove_temp_files_on_signal(): fixed
// slots of plain chars, so that a signal handler can read them safely.
constexpr std::size_t kTempPathMax = 4096;
std::mutex g_temp_mutex;

template <int N>
struct PathSlots {
  static constexpr int size = N;
  char paths[N][kTempPathMax];
  std::atomic<bool> used[N];

  void add(const std::string& p) {
    if (p.size() + 1 > kTempPathMax) return;
    std::lock_guard<std::mutex> lock(g_temp_mutex);
    for (int i = 0; i < N; ++i) {
      if (used[i].load()) continue;
      std::memcpy(paths[i], p.c_str(), p.size() + 1);
      used[i].store(true);
      return;
    }
  }
  void forget(const std::string& p) {
    std::lock_guard<std::mutex> lock(g_temp_mutex);
    for (int i = 0; i < N; ++i)
      if (used[i].load() && p == paths[i]) used[i].store(false);
  }
};
PathSlots<64> g_temp_files;  // zero-initialised: static storage
PathSlots<8> g_temp_dirs;

void register_temp(const std::string& tmp) { g_temp_files.add(tmp); }
void unregister_temp(const std::string& tmp) { g_temp_files.forget(tmp); }

// Child processes writing into the temporary directories (run_program).
constexpr int kChildSlots = 8;
std::atomic<pid_t> g_children[kChildSlots];

// Removes the entry `name` of the directory open as `dirfd`, and everything
// under it when it is a directory, with async-signal-safe calls only
// (openat, getdents64, unlinkat): for the signal handlers. Links are removed,
// never followed. `depth` bounds the recursion.
bool remove_tree_at(int dirfd, const char* name, int depth) {
  if (::unlinkat(dirfd, name, 0) == 0) return true;
  if ((errno != EISDIR && errno != EPERM) || depth > 16) return false;
  const int fd = ::openat(dirfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  alignas(8) char buf[2048];
  // passes over the directory from its start until one removes nothing
  // (removing entries while reading may skip some)
  for (int pass = 0; pass < 8; ++pass) {
    bool removed = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        // struct linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name
        unsigned short reclen;
        std::memcpy(&reclen, buf + off + 16, sizeof reclen);
        const char* entry = buf + off + 19;
        if (std::strcmp(entry, ".") != 0 && std::strcmp(entry, "..") != 0 && remove_tree_at(fd, entry, depth + 1))
          removed = true;
        off += reclen;
      }
    }
    if (!removed) break;
  }
  ::close(fd);
  return ::unlinkat(dirfd, name, AT_REMOVEDIR) == 0;
}

extern "C" void remove_temps_and_reraise(int sig) {
  const int saved = errno;
  // first stop the children that write into the temporary directories
  for (int i = 0; i < kChildSlots; ++i) {
    const pid_t pid = g_children[i].load();
    if (pid <= 0) continue;
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
  }
  for (int i = 0; i < g_temp_files.size; ++i)
    if (g_temp_files.used[i].load()) ::unlink(g_temp_files.paths[i]);
  for (int i = 0; i < g_temp_dirs.size; ++i)
    if (g_temp_dirs.used[i].load()) remove_tree_at(AT_FDCWD, g_temp_dirs.paths[i], 0);
  errno = saved;
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

namespace {
// Where the symbolic link `p` points (a relative target joined to p's
// directory), or "" when p is not a readable link.
std::string link_target(const std::string& p) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return "";
  std::string target(4096, '\0');
  const ssize_t n = ::readlink(p.c_str(), target.data(), target.size());
  if (n <= 0) return "";
  target.resize(static_cast<std::size_t>(n));
  const auto slash = p.find_last_of('/');
  if (target[0] != '/' && slash != std::string::npos) target = p.substr(0, slash + 1) + target;
  return target;
}
constexpr int kMaxLinkHops = 40;  // as the kernel's ELOOP limit
}  // namespace

int own_descriptor(const std::string& path) {
  const std::string self = "/proc/" + std::to_string(::getpid()) + "/fd/";
  std::string p = path;
  for (int hop = 0; hop < kMaxLinkHops && !p.empty(); ++hop, p = link_target(p))
    for (const std::string& pre : {std::string("/proc/self/fd/"), std::string("/dev/fd/"), self})
      if (p.size() > pre.size() && p.compare(0, pre.size(), pre) == 0 &&
          p.find_first_not_of("0123456789", pre.size()) == std::string::npos && p.size() - pre.size() < 9)
        return std::stoi(p.substr(pre.size()));
  return -1;
}

std::string output_target(const std::string& path) {
  if (path.empty()) throw InputError("no output file name given (an empty path)");
  if (own_descriptor(path) >= 0)
    throw InputError("cannot write '" + path + "': it is one of this process's open files (standard output?), and "
                     "this output is written as a new file renamed into place; name a file");
  struct stat st {};
  // A device, pipe or socket (followed through links: /dev/stdout) is not
  // a file that can be replaced by a rename.
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
    throw InputError("cannot write '" + path + "': it is not a regular file (a device, pipe or socket), and this "
                     "output is written as a new file renamed into place, which would replace it");
  std::string p = path;
  for (int hop = 0; hop < kMaxLinkHops; ++hop) {
    const std::string next = link_target(p);
    if (next.empty()) {
      if (::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        throw InputError("cannot write '" + path + "': it is a directory");
      return p;
    }
    p = next;
  }
  throw InputError("cannot write '" + path + "': too many levels of symbolic links");
}

std::string report_dir_problem(const std::string& dir) {
  if (dir.empty()) return "no directory given (an empty path)";
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0) return "";  // a new directory
  if (S_ISLNK(st.st_mode)) return "it is a symbolic link (a report replaces the directory; name the directory itself)";
  if (!S_ISDIR(st.st_mode)) return "it exists and is not a directory";
  DIR* d = ::opendir(dir.c_str());
  if (!d) return "it cannot be read (" + errno_text(errno) + ")";
  bool index = false;
  std::string foreign;
  int entries = 0;
  while (const dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (n == "." || n == "..") continue;
    ++entries;
    struct stat es {};
    const bool file = ::lstat((dir + "/" + n).c_str(), &es) == 0 && S_ISREG(es.st_mode);
    const bool png = n.size() > 4 && n.compare(n.size() - 4, 4, ".png") == 0;
    if (file && n == "index.html") index = true;
    else if (!(file && (n == "report.md" || n == "diagnosis.json" || png)) && foreign.empty()) foreign = n;
  }
  ::closedir(d);
  if (entries == 0) return "";
  if (!foreign.empty())
    return "it holds '" + foreign + "', which a diagnosis report does not write, and a report replaces the whole "
           "directory: choose a new or empty directory, or an earlier report's";
  if (!index)
    return "it is not an earlier report (no index.html), and a report replaces the whole directory: choose a new "
           "or empty directory, or an earlier report's";
  return "";
}

std::string temp_path_for(const std::string& path, const std::string& suffix) {
  static std::atomic<unsigned> counter{0};
  std::string tmp = output_target(path) + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + suffix;
  register_temp(tmp);
  return tmp;
}

void discard_temp_file(const std::string& tmp) {
  std::remove(tmp.c_str());
  unregister_temp(tmp);
}

void register_temp_dir(const std::string& dir) { g_temp_dirs.add(dir); }

void forget_temp_dir(const std::string& dir) { g_temp_dirs.forget(dir); }

void discard_temp_dir(const std::string& dir) {
  g_temp_dirs.forget(dir);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

int run_program(const std::vector<std::string>& argv, const std::vector<std::string>& env, int stdout_to) {
  if (argv.empty()) return -1;
  std::vector<char*> av, ev;
  for (const auto& s : argv) av.push_back(const_cast<char*>(s.c_str()));
  av.push_back(nullptr);
  for (const auto& s : env) ev.push_back(const_cast<char*>(s.c_str()));
  ev.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawnattr_t at;
  posix_spawn_file_actions_init(&fa);
  posix_spawnattr_init(&at);
  if (stdout_to == -2) {
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  } else if (stdout_to >= 0 && stdout_to != 1) {
    posix_spawn_file_actions_adddup2(&fa, stdout_to, 1);
  }
  // in this process's group, so that what reaches the group (a terminal's
  // Ctrl-C, Ctrl-Z or hang-up, a SIGKILL to the group) reaches it too, with
  // the default signal dispositions and none blocked
  sigset_t all, none, old;
  sigfillset(&all);
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&at, &none);
  sigset_t deflt;
  sigemptyset(&deflt);
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE}) sigaddset(&deflt, sig);
  posix_spawnattr_setsigdefault(&at, &deflt);
  posix_spawnattr_setflags(&at, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  // signals held until the child is registered, so that a handler never
  // misses it
  pthread_sigmask(SIG_BLOCK, &all, &old);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, av[0], &fa, &at, av.data(), ev.data());
  int slot = -1;
  if (rc == 0)
    for (int i = 0; i < kChildSlots && slot < 0; ++i) {
      pid_t expected = 0;
      if (g_children[i].compare_exchange_strong(expected, pid)) slot = i;
    }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) return -1;
  // waited for without reaping it first, so that its slot is cleared
  // while its pid still names it (a handler never kills a reused pid)
  siginfo_t info {};
  int w;
  do w = ::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT);
  while (w < 0 && errno == EINTR);
  if (slot >= 0) g_children[slot].store(0);
  int status = 0;
  pid_t r;
  do r = ::waitpid(pid, &status, 0);
  while (r < 0 && errno == EINTR);
  if (w < 0 || r < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

void remove_temp_files_on_signal() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) ::signal(sig, remove_temps_and_reraise);
}

void commit_temp_file(const std::string& tmp, const std::string& path, const std::string& trailer) {
  auto fail = [&](const std::string& why) {
    discard_temp_file(tmp);
    throw InputError("cannot write '" + path + "': " + why + "; the old file, if any, is unchanged");
  };
  // the file a link points to is replaced, not the link (temp_path_for put
  // tmp beside it)
  std::string target;
  try {
    target = output_target(path);
  } catch (const InputError&) {
    discard_temp_file(tmp);
    throw;
  }
  const int fd = ::open(tmp.c_str(), O_RDWR);
  if (fd < 0) fail(errno_text(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || st.st_size == 0) {
    ::close(fd);
    fail("the writer produced an empty file");
  }
  if (!trailer.empty()) {
    const off_t n = std::min<off_t>(st.st_size, static_cast<off_t>(trailer.size()) + 64);
    std::string tail(static_cast<std::size_t>(n), '\0');
    const ssize_t got = ::pread(fd, tail.data(), tail.size(), st.st_size - n);
    while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
    if (got != n || tail.size() < trailer.size() || tail.compare(tail.size() - trailer.size(), trailer.size(), trailer) != 0) {
      ::close(fd);
      fail("the file was cut short (" + std::to_string(st.st_size) + " bytes; a full disk or a file size limit?)");
    }
  }
  if (::fsync(fd) != 0) {
    const int e = errno;
    ::close(fd);
    fail(errno_text(e));
  }
  if (::close(fd) != 0) fail(errno_text(errno));
  if (std::rename(tmp.c_str(), target.c_str()) != 0) fail("rename failed: " + errno_text(errno));
  unregister_temp(tmp);
  fsync_dir_of(target);
}

bool rename_temp_into_place(const std::string& tmp, const std::string& path) {
  std::string target;
  try {
    target = output_target(path);
  } catch (const InputError&) {
    return false;
  }
  const bool ok = std::rename(tmp.c_str(), target.c_str()) == 0;
  if (ok) {
    unregister_temp(tmp);
    fsync_dir_of(target);
  }
  return ok;
}

namespace {
// Writes all of text to the open descriptor fd (`path` names it in messages).
void write_all(int fd, const std::string& path, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t w = ::write(fd, text.data() + done, text.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0)
      throw InputError("cannot write '" + path + "': write failed after " + std::to_string(done) + " of " +
                       std::to_string(text.size()) + " bytes (" + errno_text(w < 0 ? errno : ENOSPC) + ")");
    done += static_cast<std::size_t>(w);
  }
}

// Writes text into an existing device, pipe or socket (/dev/null, a named
// pipe), as a shell redirection would: it cannot be replaced by a rename,
// and a person naming one means "write into it".
void write_into_special_file(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw InputError("cannot write '" + path + "': " + errno_text(errno));
  try {
    write_all(fd, path, text);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw InputError("cannot write '" + path + "': " + errno_text(errno));
}

// Writes text to a new temporary file beside path (temp_path_for), synced to
// disk when `sync` (commit_temp_file syncs it itself), and returns its name,
// registered for removal; the caller renames it into place or discards it.
// On failure nothing is left behind and the InputError names path.
std::string write_temp(const std::string& path, const std::string& text, bool sync) {
  const std::string tmp = temp_path_for(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int e = errno;
    unregister_temp(tmp);
    throw InputError("cannot write '" + path + "': " +
                     (e == ENOENT || e == ENOTDIR ? std::string("directory missing or not writable") : errno_text(e)));
  }
  try {
    write_all(fd, path, text);
  } catch (...) {
    ::close(fd);
    discard_temp_file(tmp);
    throw;
  }
  int e = sync && ::fsync(fd) != 0 ? errno : 0;
  if (::close(fd) != 0 && e == 0) e = errno;
  if (e != 0) {
    discard_temp_file(tmp);
    throw InputError("cannot write '" + path + "': " + errno_text(e));
  }
  return tmp;
}
}  // namespace

void write_file_atomic(const std::string& path, const std::string& text) {
  if (path.empty()) throw InputError("no output file name given (an empty path)");
  // /dev/stdout, /dev/fd/N: written to the open file itself, at its offset
  // (appending under >>), as a shell redirection would; reopening or
  // renaming over what it points to would destroy a redirected file.
  if (const int own = own_descriptor(path); own >= 0) {
    write_all(own, path, text);
    return;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
    write_into_special_file(path, text);
    return;
  }
  std::string tmp;
  try {
    tmp = write_temp(path, text, /*sync=*/false);  // commit_temp_file syncs it
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + "; the old file, if any, is unchanged");
  }
  if (text.empty()) {  // commit_temp_file refuses empty files; an empty text is legitimate here
    if (!rename_temp_into_place(tmp, path)) {
      discard_temp_file(tmp);
      throw InputError("cannot write '" + path + "': rename failed");
    }
    return;
  }
  commit_temp_file(tmp, path);
}

void write_files_together(const std::vector<std::pair<std::string, std::string>>& files) {
  if (files.size() == 1) {
    write_file_atomic(files[0].first, files[0].second);
    return;
  }
  std::vector<std::pair<std::string, std::string>> temps;  // (temporary, path) of the file targets
  std::vector<std::size_t> in_place;                       // devices, pipes, own descriptors
  std::vector<std::string> written;                        // outputs already written or renamed
  const auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& p : v) s += (s.empty() ? "'" : ", '") + p + "'";
    return s;
  };
  auto discard = [&] {
    for (const auto& t : temps) discard_temp_file(t.first);
  };
  try {
    for (std::size_t k = 0; k < files.size(); ++k) {
      const auto& [path, text] = files[k];
      if (path.empty()) throw InputError("no output file name given (an empty path)");
      struct stat st {};
      if (own_descriptor(path) >= 0 ||
          (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))) {
        in_place.push_back(k);
        continue;
      }
      temps.emplace_back(write_temp(path, text, /*sync=*/true), path);
    }
    for (std::size_t k : in_place) {
      write_file_atomic(files[k].first, files[k].second);
      written.push_back(files[k].first);
    }
  } catch (const InputError& e) {
    discard();
    throw InputError(std::string(e.what()) + (written.empty() ? "; no output was changed" : "; only " + list(written) +
                                                                 " was written, no file was replaced"));
  }
  for (std::size_t i = 0; i < temps.size(); ++i) {
    if (!rename_temp_into_place(temps[i].first, temps[i].second)) {
      const int e = errno;
      for (std::size_t j = i; j < temps.size(); ++j) discard_temp_file(temps[j].first);
      throw InputError("cannot write '" + temps[i].second + "': the rename into place failed (" + errno_text(e) + ")" +
                       (written.empty() ? std::string() : "; " + list(written) + " already replaced or written"));
    }
    written.push_back(temps[i].second);
  }
}

int whole_number(const std::string& key, double v, int lo, int hi) {
  if (v != std::floor(v) || v < lo || v > hi)
    throw InputError(key + " must be a whole number between " + std::to_string(lo) + " and " + std::to_string(hi));
  return static_cast<int>(v);
}

std::vector<std::string> glider_files_in(const std::string& dir) {
  std::vector<std::string> out;
  DIR* d = opendir(dir.c_str());
  if (!d) throw InputError("cannot read directory '" + dir + "'");
  const std::string ext = ".glider.json";
  while (dirent* e = readdir(d)) {
    const std::string n = e->d_name;
    if (n.size() > ext.size() && n.compare(n.size() - ext.size(), ext.size(), ext) == 0) out.push_back(dir + "/" + n);
  }
  closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}

// ------------------------------------------------------------------ gliders

Glider glider_from_json(const json& j) {
  const Reader r;
  if (!j.is_object()) r.fail("a glider file must hold a JSON object");
  auto fit = j.find("format");
  if (fit == j.end()) r.fail("missing key 'format' (expected \"pteromys-glider/1\")");
  if (!fit->is_string() || fit->get<std::string>() != "pteromys-glider/1")
    r.fail("unknown format " + fit->dump() + " (expected \"pteromys-glider/1\")");
  Glider g;
  if (auto it = j.find("name"); it != j.end() && it->is_string()) g.name = it->get<std::string>();
  const json& mat = r.key(j, "material", "");
  g.material.thickness_m = r.number(mat, "thickness_m", "material");
  g.material.density_kg_m3 = r.number(mat, "density_kg_m3", "material");
  const json& fus = r.key(j, "fuselage", "");
  g.fuselage = r.polygon(r.key(fus, "outline_m", "fuselage"), "fuselage.outline_m");
  const json& wings = r.key(j, "wings", "");
  if (!wings.is_array()) r.fail("wings must be a list");
  for (std::size_t i = 0; i < wings.size(); ++i) {
    const std::string p = "wings[" + std::to_string(i) + "]";
    Wing w;
    w.name = r.string(wings[i], "name", p);
    w.outline = r.polygon(r.key(wings[i], "outline_m", p), p + ".outline_m");
    const json& m = r.key(wings[i], "mount", p);
    w.mount.x_m = r.number(m, "x_m", p + ".mount");
    w.mount.y_m = r.number(m, "y_m", p + ".mount");
    w.mount.angle_deg = r.number(m, "angle_deg", p + ".mount");
    g.wings.push_back(std::move(w));
  }
  if (auto it = j.find("ballast"); it != j.end()) {
    if (!it->is_array()) r.fail("ballast must be a list");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const std::string p = "ballast[" + std::to_string(i) + "]";
      const json& b = (*it)[i];
      Ballast bl;
      if (auto n = b.find("name"); b.is_object() && n != b.end() && n->is_string()) bl.name = n->get<std::string>();
      bl.mass_kg = r.number(b, "mass_kg", p);
      bl.x_m = r.number(b, "x_m", p);
      bl.y_m = r.number(b, "y_m", p);
      g.ballast.push_back(bl);
    }
  }
  return g;
}

Glider glider_from_json_text(const std::string& text) {
  return glider_from_json(parse_json(text, "the glider file"));
}

json glider_to_json(const Glider& g) {
  auto poly = [](const Polygon& p) {
    json a = json::array();
    for (const auto& v : p) a.push_back({v.x, v.y});
    return a;
  };
  json j;
  j["format"] = "pteromys-glider/1";
  j["name"] = g.name;
  j["material"] = {{"thickness_m", g.material.thickness_m}, {"density_kg_m3", g.material.density_kg_m3}};
  j["fuselage"] = {{"outline_m", poly(g.fuselage)}};
  j["wings"] = json::array();
  for (const auto& w : g.wings)
    j["wings"].push_back({{"name", w.name},
                          {"outline_m", poly(w.outline)},
                          {"mount", {{"x_m", w.mount.x_m}, {"y_m", w.mount.y_m}, {"angle_deg", w.mount.angle_deg}}}});
  j["ballast"] = json::array();
  for (const auto& b : g.ballast)
    j["ballast"].push_back({{"name", b.name}, {"mass_kg", b.mass_kg}, {"x_m", b.x_m}, {"y_m", b.y_m}});
  return j;
}

Glider load_glider(const std::string& path) {
  try {
    Glider g = glider_from_json_text(read_file(path));
    validate(g);
    return g;
  } catch (const InputError& e) {
    std::string m = e.what();
    if (m.rfind("cannot read", 0) == 0) throw;
    throw InputError(path + ": " + m);
  }
}

void save_glider(const Glider& g, const std::string& path) {
  write_file_atomic(path, glider_to_json(g).dump(2) + "\n");
}

// ------------------------------------------------------------------- models

namespace {
FlatPlateParams flat_plate_from_json(const json& p, const Reader& r, const std::string& path) {
  FlatPlateParams f;
  auto opt = [&](const char* k, double& dst) {
    if (p.contains(k)) dst = r.number(p.at(k), path + "." + k);
  };
  opt("aspect_ratio", f.aspect_ratio);
  opt("section_lift_slope_per_rad", f.section_lift_slope);
  opt("stall_deg", f.stall_deg);
  opt("stall_width_deg", f.stall_width_deg);
  opt("normal_force_90", f.normal_force_90);
  opt("edge_drag", f.edge_drag);
  opt("alpha_valid_deg", f.alpha_valid_deg);
  if (!(f.aspect_ratio > 0) || !(f.section_lift_slope > 0) || !(f.stall_width_deg > 0) ||
      !(f.alpha_valid_deg > 0) || !(f.alpha_valid_deg <= 90))
    r.fail(path + ": aspect ratio, lift slope, stall width must be positive and alpha_valid_deg in (0, 90]");
  return f;
}
json flat_plate_to_json(const FlatPlateParams& f) {
  return {{"aspect_ratio", f.aspect_ratio},
          {"section_lift_slope_per_rad", f.section_lift_slope},
          {"stall_deg", f.stall_deg},
          {"stall_width_deg", f.stall_width_deg},
          {"normal_force_90", f.normal_force_90},
          {"edge_drag", f.edge_drag},
          {"alpha_valid_deg", f.alpha_valid_deg}};
}

constexpr double kMaxCentreCoefficient = 10.0;  ///< |cd|, |cl|, |cm| a model file may hold at a centre
}  // namespace

std::shared_ptr<const CoefficientModel> model_from_json(const json& j) {
  const Reader r;
  if (!j.is_object()) r.fail("a model file must hold a JSON object");
  auto fit = j.find("format");
  if (fit == j.end() || !fit->is_string() || fit->get<std::string>() != "pteromys-model/1")
    r.fail("unknown model format " + (fit == j.end() ? std::string("(missing)") : fit->dump()) +
           " (expected \"pteromys-model/1\")");
  const std::string type = r.string(j, "type", "");
  if (type == "flat_plate") {
    const json empty = json::object();
    return std::make_shared<FlatPlateModel>(
        flat_plate_from_json(j.contains("params") ? j.at("params") : empty, r, "params"));
  }
  if (type != "rbf") r.fail("unknown model type '" + type + "' (expected \"rbf\" or \"flat_plate\")");
  const json& sc = r.key(j, "scales", "");
  RbfScales s;
  s.alpha = deg2rad(r.number(sc, "alpha_deg", "scales"));
  s.re = r.number(sc, "re", "scales");
  s.xi_l = deg2rad(r.number(sc, "xi_l_deg", "scales"));
  s.xi_t = deg2rad(r.number(sc, "xi_t_deg", "scales"));
  const double lim = deg2rad(r.number(j, "alpha_limit_deg", ""));
  if (!(lim > 0) || lim > kPi / 2) r.fail("alpha_limit_deg must be in (0, 90]");
  std::shared_ptr<const FlatPlateModel> prior;
  if (auto it = j.find("prior"); it != j.end() && !it->is_null())
    prior = std::make_shared<FlatPlateModel>(flat_plate_from_json(*it, r, "prior"));
  const json& cs = r.key(j, "centres", "");
  if (!cs.is_array() || cs.empty()) r.fail("centres must be a non-empty list");
  std::vector<RbfCentre> centres;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const std::string p = "centres[" + std::to_string(i) + "]";
    RbfCentre c;
    c.alpha = deg2rad(r.number(cs[i], "alpha_deg", p));
    c.re = r.number(cs[i], "re", p);
    c.xi_l = deg2rad(r.number(cs[i], "xi_l_deg", p));
    c.xi_t = deg2rad(r.number(cs[i], "xi_t_deg", p));
    c.value.cd = r.number(cs[i], "cd", p);
    c.value.cl = r.number(cs[i], "cl", p);
    c.value.cm = r.number(cs[i], "cm", p);
    // A plate section's coefficients are within a few units (the fit keeps
    // |cl|, cd <= 2.5 and |cm| <= 1); a value far beyond is not a model of
    // one (a unit slip or a damaged file) and would make every flight leave
    // the model's range.
    for (const auto& [name, v] : {std::pair{"cd", c.value.cd}, std::pair{"cl", c.value.cl}, std::pair{"cm", c.value.cm}})
      if (std::abs(v) > kMaxCentreCoefficient)
        r.fail(p + "." + name + " is " + fmt_number(v, 8) + "; a flat plate's coefficients lie between -" +
               fmt_number(kMaxCentreCoefficient) + " and " + fmt_number(kMaxCentreCoefficient));
    centres.push_back(c);
  }
  return std::make_shared<RbfModel>(std::move(centres), s, lim, prior);
}

json model_to_json(const CoefficientModel& m) {
  json j;
  j["format"] = "pteromys-model/1";
  j["type"] = m.kind();
  if (const auto* f = dynamic_cast<const FlatPlateModel*>(&m)) {
    j["params"] = flat_plate_to_json(f->params());
  } else if (const auto* rb = dynamic_cast<const RbfModel*>(&m)) {
    const RbfScales& s = rb->scales();
    j["alpha_limit_deg"] = rad2deg(rb->alpha_limit());
    j["scales"] = {{"alpha_deg", rad2deg(s.alpha)}, {"re", s.re}, {"xi_l_deg", rad2deg(s.xi_l)}, {"xi_t_deg", rad2deg(s.xi_t)}};
    j["prior"] = rb->prior() ? flat_plate_to_json(rb->prior()->params()) : json(nullptr);
    j["centres"] = json::array();
    for (const auto& c : rb->centres())
      j["centres"].push_back({{"alpha_deg", rad2deg(c.alpha)}, {"re", c.re}, {"xi_l_deg", rad2deg(c.xi_l)},
                              {"xi_t_deg", rad2deg(c.xi_t)}, {"cd", c.value.cd}, {"cl", c.value.cl}, {"cm", c.value.cm}});
  } else {
    throw InputError("this model kind cannot be saved: " + m.kind());
  }
  return j;
}

std::shared_ptr<const CoefficientModel> load_model(const std::string& path) {
  try {
    return model_from_json(parse_json(read_file(path), "the model file"));
  } catch (const InputError& e) {
    std::string m = e.what();
    if (m.rfind("cannot read", 0) == 0) throw;
    throw InputError(path + ": " + m);
  }
}

void save_model(const CoefficientModel& m, const std::string& path) {
  write_file_atomic(path, model_to_json(m).dump(2) + "\n");
}

namespace {
bool file_exists(const std::string& p) {
  struct stat st {};
  return !p.empty() && stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
std::string find_default_model() {
  if (const char* env = std::getenv("PTEROMYS_MODEL"); env && *env) {
    if (!file_exists(env)) throw InputError(std::string("PTEROMYS_MODEL names a missing file: ") + env);
    return env;
  }
  const std::string rel = "models/default.model.json";
  for (const std::string& dir : {std::string(PTEROMYS_INSTALL_DATADIR), std::string(PTEROMYS_SOURCE_DIR) + "/engine"}) {
    if (dir.empty() || dir == "/engine") continue;
    if (file_exists(dir + "/" + rel)) return dir + "/" + rel;
  }
  return "";
}
}  // namespace

std::string default_model_path() { return find_default_model(); }

std::shared_ptr<const CoefficientModel> default_model() {
  const std::string p = find_default_model();
  if (p.empty()) return std::make_shared<FlatPlateModel>();
  return load_model(p);
}

// ------------------------------------------------------------------ reports

json report_to_json(const Flyability& f) {
  json j;
  j["format"] = "pteromys-report/1";
  j["mass_kg"] = f.mass.mass;
  j["cg_m"] = {f.mass.cg.x, f.mass.cg.y};
  j["inertia_kg_m2"] = f.mass.inertia;
  j["mounts"] = json::array();
  for (std::size_t i = 0; i < f.mounts.size(); ++i)
    j["mounts"].push_back({{"wing", i < f.wing_names.size() ? f.wing_names[i] : std::to_string(i)},
                           {"x_m", f.mounts[i].x_m},
                           {"y_m", f.mounts[i].y_m},
                           {"angle_deg", f.mounts[i].angle_deg}});
  j["flyable"] = f.flyable;
  j["reasons"] = f.reasons;
  j["warnings"] = f.warnings;
  j["pitch_stable"] = f.pitch_stable;
  j["trim"] = json::array();
  for (const auto& t : f.trim)
    j["trim"].push_back({{"speed_m_s", t.v},
                         {"alpha_deg", rad2deg(t.gamma)},
                         {"lift_n", t.lift},
                         {"drag_n", t.drag},
                         {"dmoment_dalpha_n_m_per_rad", t.dmoment_dgamma}});
  if (f.glide.exists)
    j["glide"] = {{"alpha_deg", rad2deg(f.glide.gamma)},
                  {"speed_m_s", f.glide.speed},
                  {"glide_ratio", f.glide.ratio},
                  {"sink_rate_m_s", f.glide.sink_rate},
                  {"path_angle_deg", rad2deg(f.glide.path_angle)}};
  else
    j["glide"] = nullptr;
  if (f.pitch_stable) {
    j["neutral_point_x_m"] = f.neutral_point_x;
    j["static_margin"] = f.static_margin;
  } else {
    j["neutral_point_x_m"] = nullptr;
    j["static_margin"] = nullptr;
  }
  j["reference_chord_m"] = f.reference_chord;
  j["launches"] = json::array();
  for (const auto& l : f.launches) {
    const char* end = l.flight.end == FlightEnd::Ground ? "ground"
                      : l.flight.end == FlightEnd::TimeLimit ? "time_limit" : "unstable";
    json e = {{"speed_m_s", l.launch.speed},
              {"angle_deg", l.launch.climb_deg},
              {"height_m", l.launch.height},
              {"distance_m", l.flight.distance},
              {"flight_time_s", l.flight.flight_time},
              {"stable", l.flight.stable},
              {"end", end},
              {"max_alpha_deg", rad2deg(l.flight.max_alpha)}};
    if (!l.flight.reason.empty()) e["reason"] = l.flight.reason;
    j["launches"].push_back(e);
  }
  return j;
}

std::string trajectories_csv(const Flyability& f) {
  std::ostringstream s;
  s.precision(9);
  s << "launch,t_s,x_m,y_m,pitch_deg,speed_m_s\n";
  for (std::size_t i = 0; i < f.launches.size(); ++i)
    for (const auto& p : f.launches[i].flight.samples)
      s << i << ',' << p.t << ',' << p.x << ',' << p.y << ',' << rad2deg(p.pitch) << ',' << p.speed << '\n';
  return s.str();
}

}  // namespace pteromys
