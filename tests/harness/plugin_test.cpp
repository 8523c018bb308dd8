// The parts of evaluator plugins (harness/plugins/plugin.h, issue 31) that need no built plugin:
// the file hash, the registry of added strategies, and what an unusable library becomes. The
// plugins themselves are exercised end to end by tests/plugins/plugins_test.sh.
#include "harness/plugins/plugin.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "reference/validation.h"

namespace nurbs {
namespace {

namespace fs = std::filesystem;

// In a folder of this process's own: the file name is what an unusable plugin is named after.
fs::path write_temp(const std::string& name, const std::string& bytes) {
  const fs::path folder =
      fs::temp_directory_path() / ("nurbsbench-plugin-test-" + std::to_string(::getpid()));
  fs::create_directories(folder);
  std::ofstream(folder / name, std::ios::binary) << bytes;
  return folder / name;
}

TEST(PluginTest, Sha256MatchesTheFipsVectors) {
  // FIPS 180-2 appendix B.1 and the empty message.
  const fs::path abc = write_temp("abc", "abc");
  EXPECT_EQ(file_sha256(abc), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const fs::path empty = write_temp("empty", "");
  EXPECT_EQ(file_sha256(empty), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // B.2: 448 bits, across the padding boundary.
  const fs::path two =
      write_temp("two", "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq");
  EXPECT_EQ(file_sha256(two), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  fs::remove_all(abc.parent_path());
}

TEST(PluginTest, AMissingFileIsBadInput) {
  EXPECT_THROW(load_plugin("/nonexistent/libnothing.so"), InputError);
}

TEST(PluginTest, AnUnloadableLibraryIsAStrategyThatFails) {
  const fs::path garbage = write_temp("libgarbage-plugin.so.1", "not an ELF file\n");
  const std::string name = "garbage-plugin";
  const StrategyEntry& entry = load_plugin(garbage);
  EXPECT_EQ(entry.name, name);
  EXPECT_EQ(entry.role, "plugin");
  EXPECT_EQ(find_strategy(name), &entry);
  ASSERT_NE(strategy_library(entry), nullptr);
  EXPECT_EQ(strategy_library(entry)->path, fs::absolute(garbage).string());
  EXPECT_EQ(strategy_library(entry)->sha256, file_sha256(garbage));
  EXPECT_TRUE(entry.probe().available);
  try {
    entry.create({});
    FAIL() << "create() of an unloadable plugin returned";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("fails to load: "), std::string::npos) << e.what();
  }
  // The same file again: its name is taken now.
  EXPECT_THROW(load_plugin(garbage), InputError);
  fs::remove_all(garbage.parent_path());
}

TEST(PluginTest, ABuiltInNameCannotBeAdded) {
  EXPECT_EQ(strategy_library(*find_strategy("cpu-coxdeboor")), nullptr);
  StrategyEntry entry = *find_strategy("cpu-coxdeboor");
  EXPECT_THROW(add_strategy(entry, {"/x.so", "0"}), std::invalid_argument);
}

}  // namespace
}  // namespace nurbs
