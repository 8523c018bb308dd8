// What a hostile plugin can do to each verb (tests/harness/hostile_plugin.cpp, one library per
// misbehaviour): crash, hang, exit or print in its constructors or entry point, abort, exit(0),
// chdir, close descriptors, loop, leave the process group or eat memory in its calls, and hand
// back bytes that are not UTF-8. The main process must always end with its documented exit code,
// with results files that are valid and complete and a machine-readable output that is only ours.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_cli.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string plugin(const std::string& mode) {
  return std::string(HOSTILE_PLUGIN_DIR) + "/libhostile-" + mode + ".so";
}

// Every byte of `text` is printable ASCII or part of a UTF-8 sequence (the JSON parser already
// refused invalid UTF-8): no newline, no escape character, nothing that moves a terminal.
bool printable_line(const std::string& text) {
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
  return true;
}

json records_by_strategy(const fs::path& out) {
  const json doc = json::parse(read_text(out / "results.json"));
  json by_name = json::object();
  for (const json& r : doc["records"]) by_name[r["strategy"].get<std::string>()] = r;
  return by_name;
}

// The plugins that cannot be used, and what each one's reason says.
const std::map<std::string, std::string> kUnusable = {
    {"ctor-crash", "crashed while it was probed: SIGSEGV (Segmentation fault) in dlopen"},
    {"ctor-hang", "timed out while it was probed: no answer within 2 s (--timeout) in dlopen"},
    {"ctor-exit", "exited with status 0 in dlopen (the library's constructors) before it answered"},
    {"entry-crash",
     "crashed while it was probed: SIGSEGV (Segmentation fault) in "
     "nurbsbench_evaluator()"},
    {"entry-hang", "no answer within 2 s (--timeout) in nurbsbench_evaluator()"},
    {"struct-size", "struct_size 4294967295 is above version 1's"},
    {"abi-zero", "wrong ABI version 0 (this harness loads 1..1)"},
    {"no-entry", "missing entry points: the library exports no nurbsbench_evaluator()"},
    {"bad-name", "invalid name 'evil\\nname\\x1b[2J'"},
};

std::vector<std::string> unusable_plugin_args() {
  std::vector<std::string> args;
  for (const auto& [mode, reason] : kUnusable) args.insert(args.end(), {"--plugin", plugin(mode)});
  return args;
}

// list: every unusable plugin is unavailable with its reason and no capabilities, the JSON is
// valid (a constructor's stdout does not reach it), and the text has no raw control character.
TEST(HostilePlugins, ListShowsUnusablePluginsUnavailableWithTheirReason) {
  TempDir tmp;
  write_text(tmp / "libtext.so", "not a shared library\n");
  std::vector<std::string> args = {
      "list",     "--json",           "--timeout", "2",
      "--plugin", tmp / "libtext.so", "--plugin",  plugin("ctor-stdout")};
  const std::vector<std::string> unusable = unusable_plugin_args();
  args.insert(args.end(), unusable.begin(), unusable.end());
  const CliResult r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);  // throws on anything but our JSON
  std::map<std::string, json> strategies;
  for (const json& s : doc["strategies"]) strategies[s["name"]] = s;
  const auto expect_unusable = [&](const std::string& name, const std::string& reason) {
    ASSERT_TRUE(strategies.contains(name)) << name;
    const json& s = strategies[name];
    EXPECT_EQ(s["available"], false) << s.dump();
    EXPECT_TRUE(s["capabilities"].is_null()) << s.dump();
    EXPECT_NE(s["reason"].get<std::string>().find(reason), std::string::npos) << s.dump();
    EXPECT_TRUE(printable_line(s["reason"])) << s.dump();
  };
  expect_unusable("text", "fails to load: ");
  for (const auto& [mode, reason] : kUnusable) expect_unusable("hostile-" + mode, reason);
  EXPECT_EQ(strategies["hostile-ctor-stdout"]["available"], true);
  EXPECT_EQ(strategies["hostile-ctor-stdout"]["capabilities"]["precisions"], json({"f32", "f64"}));

  const CliResult text = run_cli({"list", "--plugin", plugin("bad-name")});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  for (const std::string& line : split_lines(text.out)) EXPECT_TRUE(printable_line(line)) << line;
}

// run: a plugin whose constructor or entry point crashes, hangs or exits costs only its own
// record, even when it is not among the strategies measured.
TEST(HostilePlugins, RunKeepsEveryRecordWhateverTheLoadDoes) {
  TempDir tmp;
  std::vector<std::string> args = {"run", "--scenes",      "patch144", "--samples",
                                   "4x4", "--repetitions", "1",        "--timeout",
                                   "2",   "--out",         tmp / "out"};
  const std::vector<std::string> unusable = unusable_plugin_args();
  args.insert(args.end(), unusable.begin(), unusable.end());
  std::string strategies = "cpu-coxdeboor";
  for (const auto& [mode, reason] : kUnusable) strategies += ",hostile-" + mode;
  args.insert(args.end(), {"--strategies", strategies});
  const CliResult r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json records = records_by_strategy(tmp.path() / "out");
  EXPECT_EQ(records.size(), kUnusable.size() + 1);
  EXPECT_EQ(records["cpu-coxdeboor"]["status"], "ok");
  for (const auto& [mode, reason] : kUnusable) {
    const json& record = records["hostile-" + mode];
    EXPECT_EQ(record["status"], "failed") << record.dump();
    EXPECT_NE(record["reason"].get<std::string>().find(reason), std::string::npos) << record.dump();
  }
  for (const std::string& line : split_lines(r.out)) EXPECT_TRUE(printable_line(line)) << line;

  // Not selected: the crashing constructor is probed, never run in this process.
  const CliResult other =
      run_cli({"run", "--plugin", plugin("ctor-crash"), "--plugin", plugin("entry-crash"),
               "--strategies", "cpu-coxdeboor", "--scenes", "patch144", "--samples", "4x4",
               "--repetitions", "1", "--out", tmp / "other"});
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_EQ(records_by_strategy(tmp.path() / "other").size(), 1u);
}

// recommend probes its plugins like run: a crashing constructor costs nothing, a chatty one does
// not reach the JSON on stdout.
TEST(HostilePlugins, RecommendSurvivesItsPluginsLoads) {
  TempDir tmp;
  const CliResult measured =
      run_cli({"run", "--strategies", "cpu-coxdeboor", "--scenes", "patch144", "--samples", "4x4",
               "--repetitions", "1", "--out", tmp / "out"});
  ASSERT_EQ(measured.exit_code, 0) << measured.err;
  const CliResult r =
      run_cli({"recommend", "--results", tmp / "out", "--tolerance", "8ulp", "--json", "--plugin",
               plugin("ctor-crash"), "--plugin", plugin("ctor-stdout")});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NO_THROW(json::parse(r.out)) << r.out;
}

// A message that is not UTF-8 and holds a newline and an escape keeps its reason, made valid and
// printable, in every output -- in one process (--isolation none) as in a child.
TEST(HostilePlugins, ReasonsSurviveInvalidBytesInBothIsolationModes) {
  for (const std::string isolation : {"process", "none"}) {
    TempDir tmp;
    const CliResult r =
        run_cli({"run", "--plugin", plugin("eval-bad-message"), "--plugin", plugin("bad-name"),
                 "--strategies", "hostile-eval-bad-message,cpu-coxdeboor,hostile-bad-name",
                 "--scenes", "patch144", "--samples", "4x4", "--repetitions", "1", "--isolation",
                 isolation, "--out", tmp / "out"});
    ASSERT_EQ(r.exit_code, 0) << isolation << ": " << r.err;
    const json records = records_by_strategy(tmp.path() / "out");
    ASSERT_EQ(records.size(), 3u) << isolation;
    EXPECT_EQ(records["cpu-coxdeboor"]["status"], "ok");
    const std::string reason = records["hostile-eval-bad-message"]["reason"];
    EXPECT_EQ(records["hostile-eval-bad-message"]["status"], "failed");
    EXPECT_NE(reason.find("bad bytes \xef\xbf\xbd"), std::string::npos) << reason;
    EXPECT_NE(reason.find("here\\nsecond line \\x1b[31mred"), std::string::npos) << reason;
    EXPECT_TRUE(printable_line(reason)) << reason;
    const std::string csv = read_text(tmp.path() / "out" / "results.csv");
    EXPECT_EQ(split_lines(csv).size(), 4u) << csv;
    for (const std::string& line : split_lines(r.out)) EXPECT_TRUE(printable_line(line)) << line;
  }
}

struct EvalCase {
  std::string mode;
  int exit_code;
  std::string message;  // in stderr
};

// eval runs the plugin in a child like run: each misbehaviour is exit 1 with its status and reason
// on one line; 0 only with every point written.
TEST(HostilePlugins, EvalIsIsolatedAndItsExitCodeSaysWhatHappened) {
  const std::vector<EvalCase> cases = {
      {"eval-abort", 1, "crashed: SIGABRT (Aborted) in evaluate"},
      {"eval-crash", 1, "crashed: SIGSEGV (Segmentation fault) in evaluate"},
      {"eval-exit0", 1, "failed: the measurement process exited with status 0 in evaluate"},
      {"prepare-hang", 1, "timed_out: no answer within 2 s (--timeout) in prepare"},
      {"eval-bad-message", 1,
       "failed: plugin hostile-eval-bad-message: evaluate returned error 1: "
       "bad bytes \xef\xbf\xbd"},
      {"ctor-crash", 1, "failed: plugin "},
      {"eval-memory", 1,
       "out_of_memory: held more than 128 MiB resident (--memory-limit) in evaluate"},
      {"eval-close-fds", 0, ""},
      {"eval-stdout", 0, ""},
      {"ctor-stdout", 0, ""},
  };
  for (const EvalCase& c : cases) {
    TempDir tmp;
    const CliResult r =
        run_cli({"eval", "--plugin", plugin(c.mode), "--strategy", "hostile-" + c.mode, "--scene",
                 "patch144", "--samples", "4x4", "--timeout", "2", "--memory-limit", "128"});
    EXPECT_EQ(r.exit_code, c.exit_code) << c.mode << ": " << r.err;
    if (c.exit_code != 0) {
      EXPECT_NE(r.err.find(c.message), std::string::npos) << c.mode << ": " << r.err;
      EXPECT_TRUE(is_one_error_line(r.err)) << c.mode << ": " << r.err;
      EXPECT_EQ(r.out, "") << c.mode;
      continue;
    }
    // stdout holds the CSV alone: what the plugin printed went to stderr.
    const std::vector<std::string> lines = split_lines(r.out);
    ASSERT_EQ(lines.size(), 17u) << c.mode << ": " << r.out;
    EXPECT_EQ(lines[0], "surface,u,v,x,y,z") << c.mode;
    EXPECT_EQ(lines[16], "0,1,1,1,1,0") << c.mode;
  }
}

// The plugin changes the working directory: a relative --out still lands where the user meant.
TEST(HostilePlugins, EvalOutIsResolvedBeforeThePluginRuns) {
  TempDir tmp;
  const fs::path before = fs::current_path();
  fs::current_path(tmp.path());
  const CliResult r = run_cli({"eval", "--plugin", plugin("eval-chdir"), "--strategy",
                               "hostile-eval-chdir", "--scene", "patch144", "--samples", "4x4",
                               "--isolation", "none", "--out", "points.csv"});
  fs::current_path(before);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(split_lines(read_text(tmp.path() / "points.csv")).size(), 17u);
}

// An output that cannot be written is bad input, said before anything is evaluated.
TEST(HostilePlugins, UnwritableOutputsAreBadInputBeforeAnyWork) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"eval", "--plugin", plugin("eval-crash"), "--strategy",
                                 "hostile-eval-crash", "--scene", "patch144", "--out",
                                 "/proc/x.csv"},
        std::vector<std::string>{"eval", "--strategy", "cpu-coxdeboor", "--scene", "patch144",
                                 "--out", "/nonexistent-folder/x.csv"},
        std::vector<std::string>{"import", "/nonexistent-model.step", "--out", "/proc/x.json"}}) {
    const CliResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_TRUE(is_one_error_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("--out = '"), std::string::npos) << r.err;
  }
}

// A grandchild that leaves the process group (setsid) does not outlive its measurement.
TEST(HostilePlugins, ASetsidGrandchildIsKilledWithItsMeasurement) {
  TempDir tmp;
  const std::string pid_file = tmp / "grandchild.pid";
  ::setenv("HOSTILE_PID_FILE", pid_file.c_str(), 1);
  const CliResult r = run_cli({"run", "--plugin", plugin("eval-setsid"), "--strategies",
                               "hostile-eval-setsid,cpu-coxdeboor", "--scenes", "patch144",
                               "--samples", "4x4", "--repetitions", "1", "--out", tmp / "out"});
  ::unsetenv("HOSTILE_PID_FILE");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(records_by_strategy(tmp.path() / "out").size(), 2u);
  const pid_t pid = std::stoi(read_text(pid_file));
  ASSERT_GT(pid, 1);
  EXPECT_NE(::kill(pid, 0), 0) << "grandchild " << pid << " is still alive";
}

TEST(HostilePlugins, PluginPathsThatAreNotFilesSayWhatTheyAre) {
  const CliResult dir = run_cli({"list", "--plugin", "/tmp"});
  EXPECT_EQ(dir.exit_code, 2);
  EXPECT_NE(dir.err.find("--plugin = /tmp: is a directory"), std::string::npos) << dir.err;
  const CliResult zero = run_cli({"list", "--plugin", "/dev/zero"});
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.err.find("--plugin = /dev/zero: is not a regular file"), std::string::npos)
      << zero.err;
}

// A library that cannot say its name goes by its file name, held to the name rule.
TEST(HostilePlugins, NamesFromFileNamesFollowTheNameRule) {
  TempDir tmp;
  write_text(tmp / "libMy Plugin!.so", "not a shared library\n");
  const CliResult r = run_cli({"list", "--json", "--plugin", tmp / "libMy Plugin!.so"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool found = false;
  const json doc = json::parse(r.out);
  for (const json& s : doc["strategies"])
    if (s["role"] == "plugin") {
      found = true;
      EXPECT_EQ(s["name"], "my-plugin-");
    }
  EXPECT_TRUE(found);
}

TEST(HostilePlugins, MemoryLimitIsCheckedAndRecorded) {
  for (const std::string bad : {"0", "15", "-1", "x", "1e3", "999999999999"}) {
    const CliResult r = run_cli({"run", "--strategies", "cpu-coxdeboor", "--scenes", "patch144",
                                 "--memory-limit", bad, "--out", "/nonexistent/never"});
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--memory-limit = '"), std::string::npos) << r.err;
  }
  TempDir tmp;
  const CliResult r =
      run_cli({"run", "--strategies", "cpu-coxdeboor", "--scenes", "patch144", "--samples", "4x4",
               "--repetitions", "1", "--memory-limit", "512", "--out", tmp / "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json settings = json::parse(read_text(tmp.path() / "out" / "results.json"))["settings"];
  EXPECT_EQ(settings["memory_limit_mib"], 512);
}

}  // namespace
}  // namespace nurbs::test
