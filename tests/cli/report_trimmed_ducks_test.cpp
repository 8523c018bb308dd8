// The report's fig8_trimmed_ducks section from a real many-ducks run: each strategy's frames per
// second is recomputed here from its record (1 / the medians of evaluate, classify and render,
// whichever it has), and the section says which phases each frame holds.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "run_cli.h"

namespace nurbs::test {
namespace {

using nlohmann::json;

TEST(CliReportTrimmedDucks, FramesPerSecondAreTheRecordsPhasesAndSayWhatTheyHold) {
  TempDir tmp;
  const std::string results = tmp / "results";
  ASSERT_EQ(run_cli({"run", "--scenes", "many-ducks-1,many-ducks-2,sphere", "--strategies",
                     "cpu-coxdeboor,cpu-horner,glu-nurbs", "--samples", "16x16", "--repetitions",
                     "1", "--threads", "1", "--out", results})
                .exit_code,
            0);
  const CliResult r =
      run_cli({"report", "--results", results, "--out", tmp / "report", "--error-images", "0",
               "--trim-masks", "0", "--python", "/bin/false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string report = read_text(tmp.path() / "report" / "REPORT.md");
  const std::size_t at = report.find("## Krishnamurthy 2007 Fig 8 as it ran");
  ASSERT_NE(at, std::string::npos) << report;
  const std::string section = report.substr(at, report.find("\n## ", at + 1) - at);

  int checked = 0;
  const json document = json::parse(read_text(results + "/results.json"));
  for (const json& rec : document["records"]) {
    if (rec["role"] == "limit" || rec["scene"] == "sphere") continue;
    double frame = rec["evaluate"]["median_s"].get<double>();
    for (const char* phase : {"classify", "render"})
      if (rec.contains("extra_phases") && rec["extra_phases"].contains(phase))
        frame += rec["extra_phases"][phase]["median_s"].get<double>();
    // The table's row for this N holds this strategy's cell, formatted as report_number does.
    const std::string n = rec["scene"].get<std::string>().substr(std::string("many-ducks-").size());
    const std::size_t row = section.find("\n| " + n + " |");
    ASSERT_NE(row, std::string::npos) << section;
    const std::string line = section.substr(row + 1, section.find('\n', row + 1) - row - 1);
    EXPECT_NE(line.find(fmt::format("| {:.3g} ", 1 / frame)), std::string::npos)
        << rec["strategy"] << " " << n << ": " << line;
    ++checked;
  }
  EXPECT_EQ(checked, 6);
  EXPECT_NE(section.find("| cpu-coxdeboor | evaluate + classify (no draw path) |"),
            std::string::npos)
      << section;
  EXPECT_NE(section.find("| glu-nurbs | evaluate (no draw path), untrimmed |"), std::string::npos);
  // The untrimmed scene is not a point of this chart (the run that made the set, shown as the
  // command to regenerate it, did measure it).
  const std::size_t code = section.find("```sh\n");
  ASSERT_NE(code, std::string::npos) << section;
  const std::string shown =
      section.substr(0, code) + section.substr(section.find("```\n", code + 6));
  EXPECT_EQ(shown.find("sphere"), std::string::npos) << section;
  EXPECT_NE(section.find("--scenes many-ducks-1,many-ducks-2,sphere"), std::string::npos)
      << section;
}

}  // namespace
}  // namespace nurbs::test
