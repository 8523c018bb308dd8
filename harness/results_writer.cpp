#include "harness/results_writer.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "harness/atomic_file.h"
#include "reference/validation.h"
#include "scenes/json_error.h"
#include "scenes/scene_json.h"

namespace nurbs {

namespace {

// `text` (a value's dump(1)) as an element of an array at depth 1 of a dump(1) document: every
// line two spaces further in.
std::string as_array_element(const std::string& text) {
  std::string out = "  ";
  out.reserve(text.size() + text.size() / 8);
  for (const char c : text) {
    out += c;
    if (c == '\n') out += "  ";
  }
  return out;
}

}  // namespace

ResultsWriter::ResultsWriter(std::filesystem::path directory, nlohmann::json machine,
                             nlohmann::json settings)
    : directory_(std::move(directory)),
      machine_(std::move(machine)),
      settings_(std::move(settings)),
      csv_(csv_header() + "\n") {
  std::filesystem::create_directories(directory_);
  flush();
}

void ResultsWriter::append(const Record& record) {
  records_.push_back(record);
  record_texts_.push_back(as_array_element(record_to_json(record).dump(1)));
  csv_ += csv_row(record) + "\n";
  flush();
}

// The document as nlohmann::json::dump(1) writes it, the records spliced into its empty
// "records" array (keys are sorted, strings escape their newlines, so the array's text is found
// unambiguously at depth 1).
void ResultsWriter::flush() const {
  const nlohmann::json document = {{"format", kResultsFormat},
                                   {"machine", machine_},
                                   {"settings", settings_},
                                   {"records", nlohmann::json::array()}};
  std::string text = document.dump(1);
  if (!record_texts_.empty()) {
    const std::string_view empty_records = "\n \"records\": []";
    const std::size_t at = text.find(empty_records);
    std::string records = "\n \"records\": [\n";
    for (std::size_t i = 0; i < record_texts_.size(); ++i) {
      if (i > 0) records += ",\n";
      records += record_texts_[i];
    }
    records += "\n ]";
    text.replace(at, empty_records.size(), records);
  }
  write_file_atomically(directory_ / "results.json", text + "\n");
  write_file_atomically(directory_ / "results.csv", csv_);
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
