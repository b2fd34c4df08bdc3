#include "pteromys/io.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <thread>

#include <csignal>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.hpp"

using namespace pteromys;

// Every file of the broken corpus is rejected with its own message (the
// fragment in tests/data/broken/expected.json), never a crash.
TEST(GliderFiles, BrokenCorpusIsRejectedWithItsMessage) {
  const auto expected = parse_json(read_file(test::source_path("tests/data/broken/expected.json")), "manifest");
  ASSERT_GE(expected.size(), 20u);
  for (const auto& [file, fragment] : expected.items()) {
    const std::string path = test::source_path("tests/data/broken/" + file);
    try {
      load_glider(path);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(fragment.get<std::string>()), std::string::npos)
          << file << ": message was: " << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << file << ": message must be one line";
    }
  }
}

TEST(GliderFiles, MissingFileAndDirectoryAreNamed) {
  try {
    load_glider("/nonexistent/x.glider.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  }
  EXPECT_THROW(load_glider("/tmp"), InputError);
}

// Writing and reading back gives the same glider (every example).
TEST(GliderFiles, RoundTripPreservesEveryNumber) {
  for (const auto& [path, g] : test::examples()) {
    const Glider h = glider_from_json(glider_to_json(g));
    ASSERT_EQ(h.wings.size(), g.wings.size());
    EXPECT_EQ(h.name, g.name);
    EXPECT_EQ(h.material.thickness_m, g.material.thickness_m);
    for (std::size_t j = 0; j < g.wings.size(); ++j) {
      EXPECT_EQ(h.wings[j].name, g.wings[j].name);
      EXPECT_EQ(h.wings[j].mount.angle_deg, g.wings[j].mount.angle_deg);
      ASSERT_EQ(h.wings[j].outline.size(), g.wings[j].outline.size());
      for (std::size_t i = 0; i < g.wings[j].outline.size(); ++i) {
        EXPECT_EQ(h.wings[j].outline[i].x, g.wings[j].outline[i].x);
        EXPECT_EQ(h.wings[j].outline[i].y, g.wings[j].outline[i].y);
      }
    }
    EXPECT_EQ(h.ballast.size(), g.ballast.size());
  }
}

TEST(GliderFiles, AtomicWriteLeavesNoFileWhenDirectoryIsMissing) {
  EXPECT_THROW(write_file_atomic("/nonexistent-dir/out.json", "x"), InputError);
}

// Model files: RBF and flat-plate models survive a round trip bit for bit in
// their outputs.
TEST(ModelFiles, RoundTripGivesTheSameCoefficients) {
  std::vector<RbfCentre> cs{{deg2rad(4), 2e4, 0.1, -0.2, {0.05, 0.4, -0.01}},
                            {deg2rad(12), 3e4, -0.3, 0.0, {0.12, 0.7, -0.05}}};
  const RbfModel rbf(cs, RbfScales{}, deg2rad(30), std::make_shared<FlatPlateModel>());
  FlatPlateParams fpp;
  fpp.aspect_ratio = 3.3;
  const FlatPlateModel fp(fpp);
  for (const CoefficientModel* m : {static_cast<const CoefficientModel*>(&rbf), static_cast<const CoefficientModel*>(&fp)}) {
    const auto back = model_from_json(parse_json(model_to_json(*m).dump(), "model"));
    EXPECT_EQ(back->kind(), m->kind());
    for (double a : {-0.3, -0.05, 0.0, 0.1, 0.25}) {
      const ElementState e{a, 2.5e4, 0.2, -0.1};
      const Coefficients x = m->eval(e), y = back->eval(e);
      EXPECT_NEAR(x.cd, y.cd, 1e-12);
      EXPECT_NEAR(x.cl, y.cl, 1e-12);
      EXPECT_NEAR(x.cm, y.cm, 1e-12);
    }
  }
}

TEST(ModelFiles, BadModelFilesAreRejected) {
  const char* bad[] = {
      R"({"format": "pteromys-model/1", "type": "magic"})",
      R"({"format": "other/1", "type": "rbf"})",
      R"({"format": "pteromys-model/1", "type": "rbf", "alpha_limit_deg": 30,
          "scales": {"alpha_deg": 8, "re": 20000, "xi_l_deg": 30, "xi_t_deg": 30}, "centres": []})",
      R"({"format": "pteromys-model/1", "type": "rbf", "alpha_limit_deg": 30,
          "scales": {"alpha_deg": 0, "re": 20000, "xi_l_deg": 30, "xi_t_deg": 30},
          "centres": [{"alpha_deg": 1, "re": 1, "xi_l_deg": 0, "xi_t_deg": 0, "cd": 0, "cl": 0, "cm": 0}]})",
      R"({"format": "pteromys-model/1", "type": "flat_plate", "params": {"aspect_ratio": -1}})",
  };
  for (const char* t : bad) EXPECT_THROW(model_from_json(parse_json(t, "model")), InputError) << t;
}

// The report carries every key of spec/formats.md with the right types.
TEST(Report, HasTheSpecKeys) {
  const auto g = test::examples().front().second;
  std::vector<std::string> names;
  for (const auto& w : g.wings) names.push_back(w.name);
  const auto j = report_to_json(analyse(mount(g, default_model()), names));
  EXPECT_EQ(j.at("format"), "pteromys-report/1");
  for (const char* k : {"mass_kg", "inertia_kg_m2"}) EXPECT_TRUE(j.at(k).is_number()) << k;
  EXPECT_EQ(j.at("cg_m").size(), 2u);
  EXPECT_EQ(j.at("mounts").size(), g.wings.size());
  EXPECT_TRUE(j.at("flyable").is_boolean());
  EXPECT_TRUE(j.at("reasons").is_array());
  ASSERT_EQ(j.at("launches").size(), 6u);
  for (const auto& l : j.at("launches"))
    for (const char* k : {"speed_m_s", "angle_deg", "height_m", "distance_m", "flight_time_s"})
      EXPECT_TRUE(l.at(k).is_number()) << k;
}

namespace {
std::string fresh_dir() {
  char tmpl[] = "/tmp/pteromys-out-XXXXXX";
  return mkdtemp(tmpl);
}
void put(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
}  // namespace

// Links are written through, never replaced; what a rename would destroy or
// cannot reach is refused by name.
TEST(OutputPaths, LinksAreWrittenThroughAndSpecialFilesRefused) {
  const std::string d = fresh_dir();
  ASSERT_EQ(::mkdir((d + "/sub").c_str(), 0777), 0);
  ASSERT_EQ(::symlink("sub/real.json", (d + "/link.json").c_str()), 0);
  EXPECT_EQ(output_target(d + "/link.json"), d + "/sub/real.json");
  write_file_atomic(d + "/link.json", "{}\n");
  struct stat st {};
  ASSERT_EQ(::lstat((d + "/link.json").c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  EXPECT_EQ(read_file(d + "/sub/real.json"), "{}\n");
  ASSERT_EQ(::symlink("b", (d + "/a").c_str()), 0);
  ASSERT_EQ(::symlink("a", (d + "/b").c_str()), 0);
  auto message = [](const std::string& p) {
    try {
      output_target(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(d + "/a").find("too many levels of symbolic links"), std::string::npos);
  EXPECT_NE(message("").find("empty path"), std::string::npos);
  EXPECT_NE(message(d + "/sub").find("it is a directory"), std::string::npos);
  EXPECT_NE(message("/dev/null").find("not a regular file"), std::string::npos);
  // written into, as a redirection would: /dev/null stays a device
  write_file_atomic("/dev/null", "discarded\n");
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  EXPECT_THROW(write_file_atomic("", "x"), InputError);
}

// An empty text is a legitimate output (commit_temp_file refuses empty
// files, so it takes its own rename): the old contents go and no temporary
// file stays beside it; a directory in the way is refused before anything
// is written.
TEST(OutputPaths, AnEmptyTextReplacesAFileWholly) {
  const std::string d = fresh_dir();
  put(d + "/out.csv", "old contents\n");
  write_file_atomic(d + "/out.csv", "");
  EXPECT_EQ(read_file(d + "/out.csv"), "");
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(d)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"out.csv"});
  // a directory in the way: refused by name, nothing left in the folder
  ASSERT_EQ(::mkdir((d + "/dir.csv").c_str(), 0777), 0);
  EXPECT_THROW(write_file_atomic(d + "/dir.csv", ""), InputError);
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(d)) n += e.path().filename() != "dir.csv";
  EXPECT_EQ(n, 1u);
}

// A report may replace only a new, empty or earlier report directory.
TEST(OutputPaths, ReportDirectoryHoldsOnlyAReport) {
  const std::string d = fresh_dir();
  EXPECT_EQ(report_dir_problem(d + "/new"), "");
  EXPECT_EQ(report_dir_problem(d), "");  // empty
  put(d + "/index.html", "<html></html>");
  put(d + "/report.md", "#");
  put(d + "/effects.png", "png");
  put(d + "/diagnosis.json", "{}");
  EXPECT_EQ(report_dir_problem(d), "");
  put(d + "/notes.txt", "mine");
  EXPECT_NE(report_dir_problem(d).find("'notes.txt'"), std::string::npos);
  std::remove((d + "/notes.txt").c_str());
  std::remove((d + "/index.html").c_str());
  EXPECT_NE(report_dir_problem(d).find("no index.html"), std::string::npos);
  put(d + "/index.html", "<html></html>");
  ASSERT_EQ(::mkdir((d + "/plots").c_str(), 0777), 0);  // a subdirectory is not the report's
  EXPECT_NE(report_dir_problem(d).find("'plots'"), std::string::npos);
  EXPECT_NE(report_dir_problem(d + "/report.md").find("not a directory"), std::string::npos);
  ASSERT_EQ(::symlink(d.c_str(), (d + "-link").c_str()), 0);
  EXPECT_NE(report_dir_problem(d + "-link").find("symbolic link"), std::string::npos);
  std::remove((d + "-link").c_str());
}

namespace {
bool path_exists(const std::string& p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0;
}
}  // namespace

// A signal while a temporary directory is being filled (a report being
// rendered, a dataset being generated) removes that directory with all
// that is in it, after stopping the program that writes into it; links in it
// are removed, not followed; the process then ends by the signal. Run in a
// forked child, which installs the handlers and signals itself.
TEST(OutputPaths, ASignalRemovesTemporaryDirectoriesAndStopsTheirWriter) {
  const std::string d = fresh_dir();
  const std::string tmp = d + "/rep.tmp-1";
  const std::string outside = d + "/keep";
  ASSERT_EQ(::mkdir(outside.c_str(), 0777), 0);
  put(outside + "/mine.txt", "keep me");
  ASSERT_EQ(::mkdir(tmp.c_str(), 0777), 0);
  // more entries than one read of the directory returns (2 KB of entries),
  // a nested directory two levels deep, links to a file and a directory
  // outside, and a file with no write permission
  for (int i = 0; i < 300; ++i) put(tmp + "/plot-with-a-long-name-" + std::to_string(i) + ".png", "png");
  ASSERT_EQ(::mkdir((tmp + "/gliders").c_str(), 0777), 0);
  ASSERT_EQ(::mkdir((tmp + "/gliders/deeper").c_str(), 0777), 0);
  put(tmp + "/gliders/deeper/a.glider.json", "{}");
  ASSERT_EQ(::symlink((outside + "/mine.txt").c_str(), (tmp + "/link-to-file").c_str()), 0);
  ASSERT_EQ(::symlink(outside.c_str(), (tmp + "/link-to-dir").c_str()), 0);
  put(tmp + "/read-only.html", "x");
  ::chmod((tmp + "/read-only.html").c_str(), 0444);
  const std::string pidfile = d + "/writer.pid";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    remove_temp_files_on_signal();
    register_temp_dir(tmp);
    // a writer that would run for a minute, writing into the directory;
    // the signal comes from a thread once it has started
    std::thread killer([&] {
      for (int i = 0; i < 500 && !path_exists(pidfile); ++i) ::usleep(10000);
      ::usleep(50000);
      ::kill(::getpid(), SIGTERM);
    });
    killer.detach();
    run_program({"/bin/sh", "-c", "echo $$ > '" + pidfile + "'; while :; do echo x >> '" + tmp +
                 "/growing.txt'; sleep 0.01; done"},
                {"PATH=/usr/bin:/bin"});
    ::_exit(3);  // not reached: the signal ends the process
  }
  // waited for at most 30 s: a handler that hangs fails this test, not the suite
  int status = 0;
  pid_t w = 0;
  for (int i = 0; i < 3000 && (w = ::waitpid(child, &status, WNOHANG)) == 0; ++i) ::usleep(10000);
  if (w == 0) {
    ::kill(child, SIGKILL);
    ::waitpid(child, &status, 0);
  }
  ASSERT_EQ(w, child) << "the signalled process did not end within 30 s";
  ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(path_exists(tmp)) << tmp << " left behind";
  EXPECT_EQ(read_file(outside + "/mine.txt"), "keep me");  // links were not followed
  // the writer is gone too (killed, not orphaned)
  const std::string pid = read_file(pidfile);
  ASSERT_FALSE(pid.empty());
  ::usleep(100000);
  const bool running = ::kill(std::stoi(pid), 0) == 0;
  if (running) ::kill(std::stoi(pid), SIGKILL);  // a failed test leaves no endless writer behind
  EXPECT_FALSE(running) << "the writer " << pid << " still ran";
}

// run_program runs without a shell and reports the exit status.
TEST(OutputPaths, RunProgramReportsTheExitStatus) {
  EXPECT_EQ(run_program({"/bin/sh", "-c", "exit 7"}, {}), 7);
  EXPECT_EQ(run_program({"/bin/true"}, {}), 0);
  EXPECT_EQ(run_program({"/no/such/program"}, {}), -1);  // could not be started
  EXPECT_EQ(run_program({"/bin/sh", "-c", "kill -TERM $$"}, {}), 128 + SIGTERM);
}

// The path helpers every command shares (as basename(1) and dirname(1) would
// split the names, worked by hand), and the key a glider file gets.
TEST(OutputPaths, FileNamesStemsAndGliderKeys) {
  EXPECT_EQ(directory_of("a/b/c.txt"), "a/b");
  EXPECT_EQ(directory_of("c.txt"), ".");
  EXPECT_EQ(directory_of("/c.txt"), "/");
  EXPECT_EQ(file_name("a.d/b/c.tar.gz"), "c.tar.gz");
  EXPECT_EQ(file_name("c"), "c");
  EXPECT_EQ(file_name("a/"), "");
  EXPECT_EQ(file_stem("clips.2026/throw.2.avi"), "throw");  // a dot in the directory is not the stem's
  EXPECT_EQ(file_stem(".avi"), ".avi");
  EXPECT_EQ(file_stem("a/"), "");
  EXPECT_EQ(safe_name("my glider, v2"), "my_glider__v2");
  EXPECT_EQ(safe_name("t01-a_b.c", "-_"), "t01-a_b_c");
  EXPECT_EQ(glider_key_of("x/t01-rectangular.glider.json"), "t01-rectangular");
  EXPECT_EQ(glider_key_of("x/wing.v2.json"), "wing.v2");
  EXPECT_EQ(glider_key_of("my glider, v2.glider.json"), "my_glider__v2");
  EXPECT_EQ(glider_key_of("x/.json"), ".json");  // nothing would be left: kept whole
}

// Well-formed UTF-8 as Unicode's table 3-7 defines it, by hand: overlong
// forms, surrogates and code points above U+10FFFF are ill-formed.
TEST(OutputPaths, Utf8IsCheckedAsUnicodeDefinesIt) {
  EXPECT_EQ(first_invalid_utf8("plain ascii"), std::string::npos);
  EXPECT_EQ(first_invalid_utf8("vol \xC3\xA9t\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9B\xA9"), std::string::npos);  // é € 🛩
  EXPECT_EQ(first_invalid_utf8("f\xE9,g"), 1u);            // Latin-1 é
  EXPECT_EQ(first_invalid_utf8("ab\xC0\xAF"), 2u);         // overlong '/'
  EXPECT_EQ(first_invalid_utf8("\xE0\x80\xAF"), 0u);       // overlong, three bytes
  EXPECT_EQ(first_invalid_utf8("\xED\xA0\x80"), 0u);       // a surrogate (U+D800)
  EXPECT_EQ(first_invalid_utf8("\xF4\x90\x80\x80"), 0u);   // above U+10FFFF
  EXPECT_EQ(first_invalid_utf8("x\xE2\x82"), 1u);          // cut off at the end
  EXPECT_EQ(printable_utf8("f\xE9t\xC3\xA9"), "f\\xE9t\xC3\xA9");
  EXPECT_EQ(hex_byte(0x00), "00");
  EXPECT_EQ(hex_byte(0x0A), "0A");
  EXPECT_EQ(hex_byte(0xE9), "E9");
  EXPECT_EQ(hex_byte(0xFF), "FF");
}

// CSV cells as a tracker or a spreadsheet writes them are read; what strtod
// alone would also take (hexadecimal, inf, nan) is refused with the cell
// named, and a long cell is quoted short.
TEST(CsvCells, DecimalNumbersAreReadAndOthersNamed) {
  EXPECT_EQ(parse_decimal("1.5E-3", "w"), 1.5e-3);
  EXPECT_EQ(parse_decimal("+2", "w"), 2.0);
  EXPECT_EQ(parse_decimal(".5", "w"), 0.5);
  EXPECT_EQ(parse_decimal("-0", "w"), 0.0);
  EXPECT_EQ(parse_decimal("1E+05", "w"), 1e5);
  EXPECT_EQ(parse_decimal("1e-400", "w"), 0.0);  // underflows to zero, as strtod
  const auto message = [](const std::string& cell) {
    try {
      parse_decimal(cell, "f.csv line 3 x_m");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("0x1A"), "f.csv line 3 x_m: '0x1A' is not a decimal number");
  EXPECT_EQ(message("-0X1p3"), "f.csv line 3 x_m: '-0X1p3' is not a decimal number");
  EXPECT_EQ(message("abc"), "f.csv line 3 x_m: 'abc' is not a number");
  EXPECT_EQ(message("info"), "f.csv line 3 x_m: 'info' is not a number");
  EXPECT_EQ(message("nancy"), "f.csv line 3 x_m: 'nancy' is not a number");
  EXPECT_EQ(message("+-inf"), "f.csv line 3 x_m: '+-inf' is not a number");
  EXPECT_EQ(message(""), "f.csv line 3 x_m: '' is not a number");
  EXPECT_EQ(message("1.2.3"), "f.csv line 3 x_m: '1.2.3' is not a number");
  EXPECT_EQ(message("NaN"), "f.csv line 3 x_m: NaN or infinite value 'NaN'");
  EXPECT_EQ(message("-Infinity"), "f.csv line 3 x_m: NaN or infinite value '-Infinity'");
  EXPECT_EQ(message("1e999"), "f.csv line 3 x_m: '1e999' is beyond the range of a number");
  EXPECT_EQ(message(std::string(5000, '9')),
            "f.csv line 3 x_m: '" + std::string(37, '9') + "...' is beyond the range of a number");
  // 30 two-byte characters: cut at byte 36, between characters
  std::string accents;
  for (int i = 0; i < 30; ++i) accents += "\xC3\xA9";
  EXPECT_EQ(quoted_cell(accents), "'" + accents.substr(0, 36) + "...'");
  EXPECT_EQ(first_invalid_utf8(quoted_cell(accents)), std::string::npos);
}

TEST(CsvCells, CellsLoseTheirSurroundingWhiteSpaceAndQuotes) {
  EXPECT_EQ(split_csv_line("a, b ,\t1.5\t,\"q\"\r"), (std::vector<std::string>{"a", "b", "1.5", "q"}));
  EXPECT_EQ(split_csv_line("a,"), (std::vector<std::string>{"a", ""}));
}
