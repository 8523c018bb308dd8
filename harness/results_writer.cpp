#include "harness/results_writer.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "harness/atomic_file.h"
#include "reference/validation.h"
#include "scenes/json_error.h"
#include "scenes/scene_json.h"

namespace nurbs {

ResultsWriter::ResultsWriter(std::filesystem::path directory, nlohmann::json machine,
                             nlohmann::json settings)
    : directory_(std::move(directory)),
      machine_(std::move(machine)),
      settings_(std::move(settings)) {
  std::filesystem::create_directories(directory_);
  flush();
}

void ResultsWriter::append(const Record& record) {
  records_.push_back(record);
  flush();
}

void ResultsWriter::flush() const {
  nlohmann::json document = {{"format", kResultsFormat},
                             {"machine", machine_},
                             {"settings", settings_},
                             {"records", nlohmann::json::array()}};
  std::string csv = csv_header() + "\n";
  for (const Record& r : records_) {
    document["records"].push_back(record_to_json(r));
    csv += csv_row(r) + "\n";
  }
  write_file_atomically(directory_ / "results.json", document.dump(1) + "\n");
  write_file_atomically(directory_ / "results.csv", csv);
}

ResultsFile read_results(const std::filesystem::path& directory_or_file) {
  const std::filesystem::path path = std::filesystem::is_directory(directory_or_file)
                                         ? directory_or_file / "results.json"
                                         : directory_or_file;
  const nlohmann::json document = read_json_strictly(path, "results");
  ResultsFile out;
  try {
    if (document.value("format", "") != kResultsFormat)
      throw InputError(fmt::format("{}: format = {}: must be \"{}\"", path.string(),
                                   document.value("format", "(missing)"), kResultsFormat));
    out.machine = document.value("machine", nlohmann::json::object());
    out.settings = document.value("settings", nlohmann::json::object());
    const auto& records = document.at("records");
    for (std::size_t i = 0; i < records.size(); ++i)
      out.records.push_back(record_from_json(records[i]));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(
        fmt::format("{}: not a nurbsbench results file: {}", path.string(), json_error_text(e)));
  }
  return out;
}

}  // namespace nurbs
