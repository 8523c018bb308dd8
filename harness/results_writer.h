// Writes DIR/results.json (settings, machine, every record) and DIR/results.csv after every
// record, each replaced atomically, so an interrupted run keeps everything it measured.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
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
};

struct ResultsFile {
  nlohmann::json machine, settings;
  std::vector<Record> records;
};
// Reads DIR/results.json (or a results.json path). Throws InputError naming the file.
ResultsFile read_results(const std::filesystem::path& directory_or_file);

}  // namespace nurbs
