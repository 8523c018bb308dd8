// Writes DIR/results.json (settings, machine, every record) and DIR/results.csv after every
// record, each replaced atomically, so an interrupted run keeps everything it measured. Each
// record is serialised once, when appended: rebuilding the whole document per record made the
// main job's 1,280 appends quadratic (about 25 ms each by the end, half a minute in all).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/record.h"

namespace nurbs {

inline constexpr std::string_view kResultsFormat = "nurbsbench-results/1";

class ResultsWriter {
 public:
  ResultsWriter(std::filesystem::path directory, nlohmann::json machine, nlohmann::json settings);
  void append(const Record& record);
  const std::vector<Record>& records() const { return records_; }

 private:
  void flush() const;
  std::filesystem::path directory_;
  nlohmann::json machine_, settings_;
  std::vector<Record> records_;
  // Each record's text as it stands in results.json (nlohmann's dump(1) at the records array's
  // depth), and the CSV so far.
  std::vector<std::string> record_texts_;
  std::string csv_;
};

struct ResultsFile {
  nlohmann::json machine, settings;
  std::vector<Record> records;
};
// Reads DIR/results.json (or a results.json path). Throws InputError naming the file.
ResultsFile read_results(const std::filesystem::path& directory_or_file);

}  // namespace nurbs
