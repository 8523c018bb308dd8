#include "harness/record.h"

#include <fmt/format.h>

#include <array>
#include <nlohmann/json.hpp>

namespace nurbs {

using nlohmann::json;

std::string_view to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::unavailable:
      return "unavailable";
    case Status::failed:
      return "failed";
    case Status::refused:
      return "refused";
    case Status::out_of_memory:
      return "out_of_memory";
    case Status::crashed:
      return "crashed";
    case Status::timed_out:
      return "timed_out";
  }
  return "failed";
}

bool parse_status(std::string_view text, Status& out) {
  for (Status s : kAllStatuses)
    if (to_string(s) == text) {
      out = s;
      return true;
    }
  return false;
}

namespace {

json phase_to_json(const PhaseStats& p) {
  return {{"min_s", p.min_s}, {"median_s", p.median_s}, {"max_s", p.max_s}};
}
PhaseStats phase_from_json(const json& j) {
  return {j.value("min_s", 0.0), j.value("median_s", 0.0), j.value("max_s", 0.0)};
}
// JSON has no Inf/NaN: non-finite metrics are written as null and read back as +Inf.
json finite_or_null(double x) {
  return std::isfinite(x) ? json(x) : json(nullptr);
}
double number_or_inf(const json& j, const char* key) {
  if (!j.contains(key) || j[key].is_null()) return std::numeric_limits<double>::infinity();
  return j[key].get<double>();
}

// CSV fields: numbers in shortest round-trip form; text quoted when it needs to be (RFC 4180).
std::string csv_text(std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c == '\n' || c == '\r' ? ' ' : c;
  }
  return quoted + "\"";
}

json accuracy_to_json(const Accuracy& a) {
  json j = {{"max_abs", finite_or_null(a.max_abs)},
            {"rms_abs", finite_or_null(a.rms_abs)},
            {"max_rel", finite_or_null(a.max_rel)},
            {"max_ulp", finite_or_null(a.max_ulp)},
            {"non_finite", a.non_finite},
            {"worst", {{"surface", a.worst_surface}, {"u", a.worst_u}, {"v", a.worst_v}}}};
  if (a.max_normal_angle_deg) j["max_normal_angle_deg"] = finite_or_null(*a.max_normal_angle_deg);
  if (a.trim) {
    json trim = {{"band", a.trim->band},
                 {"inside_samples", a.trim->inside},
                 {"boundary_samples", a.trim->boundary}};
    if (a.trim->misclassified) trim["misclassified"] = *a.trim->misclassified;
    if (a.trim->misclassified_rate) trim["misclassified_rate"] = *a.trim->misclassified_rate;
    j["trim"] = trim;
  }
  return j;
}

Accuracy accuracy_from_json(const json& a) {
  Accuracy r;
  r.max_abs = number_or_inf(a, "max_abs");
  r.rms_abs = number_or_inf(a, "rms_abs");
  r.max_rel = number_or_inf(a, "max_rel");
  r.max_ulp = number_or_inf(a, "max_ulp");
  r.non_finite = a.value("non_finite", std::size_t{0});
  if (a.contains("worst")) {
    r.worst_surface = a["worst"].value("surface", 0);
    r.worst_u = a["worst"].value("u", 0.0);
    r.worst_v = a["worst"].value("v", 0.0);
  }
  if (a.contains("max_normal_angle_deg"))
    r.max_normal_angle_deg = number_or_inf(a, "max_normal_angle_deg");
  if (a.contains("trim") && a["trim"].is_object()) {
    const json& t = a["trim"];
    TrimAccuracy trim;
    trim.band = t.value("band", kDefaultTrimBand);
    trim.inside = t.value("inside_samples", std::size_t{0});
    trim.boundary = t.value("boundary_samples", std::size_t{0});
    if (t.contains("misclassified")) trim.misclassified = t["misclassified"].get<std::size_t>();
    if (t.contains("misclassified_rate"))
      trim.misclassified_rate = t["misclassified_rate"].get<double>();
    r.trim = trim;
  }
  return r;
}

}  // namespace

json record_to_json(const Record& r) {
  json j = {
      {"scene", r.scene},
      {"strategy", r.strategy},
      {"role", r.role},
      {"device", {{"name", r.device.name}, {"kind", r.device.kind}, {"details", r.device.details}}},
      {"precision", r.precision},
      {"sampling", r.sampling},
      {"samples", r.samples},
      {"points", r.points},
      {"surfaces", r.surfaces},
      {"repetitions", r.repetitions},
      {"setup_s", r.setup_s},
      {"upload", phase_to_json(r.upload)},
      {"evaluate", phase_to_json(r.evaluate)},
      {"read_back", phase_to_json(r.read_back)},
      {"end_to_end", phase_to_json(r.end_to_end)},
      {"throughput_pts_per_s", r.throughput_pts_per_s},
      {"accuracy", r.accuracy ? accuracy_to_json(*r.accuracy) : json(nullptr)},
      {"status", to_string(r.status)},
      {"reason", r.reason}};
  if (!r.trimming.empty()) j["trimming"] = r.trimming;
  if (!r.library.empty()) j["library"] = {{"path", r.library}, {"sha256", r.library_sha256}};
  if (r.device_evaluate_median_s) j["device_evaluate_median_s"] = *r.device_evaluate_median_s;
  if (!r.device_phase_median_s.empty()) j["device_phase_median_s"] = r.device_phase_median_s;
  if (!r.extra_phases.empty()) {
    json phases = json::object();
    for (const auto& [name, stats] : r.extra_phases) phases[name] = phase_to_json(stats);
    j["extra_phases"] = phases;
  }
  if (!r.figures.empty()) {
    json figures = json::object();
    for (const auto& [name, value] : r.figures) figures[name] = finite_or_null(value);
    j["figures"] = figures;
  }
  return j;
}

Record record_from_json(const json& j) {
  Record r;
  r.scene = j.at("scene").get<std::string>();
  r.strategy = j.at("strategy").get<std::string>();
  r.role = j.value("role", "");
  if (j.contains("device")) {
    r.device.name = j["device"].value("name", "");
    r.device.kind = j["device"].value("kind", "");
    if (j["device"].contains("details"))
      r.device.details = j["device"]["details"].get<std::map<std::string, std::string>>();
  }
  r.precision = j.value("precision", "");
  r.sampling = j.value("sampling", "");
  r.samples = j.value("samples", "");
  r.points = j.value("points", std::size_t{0});
  r.surfaces = j.value("surfaces", std::size_t{0});
  r.repetitions = j.value("repetitions", 0);
  r.setup_s = j.value("setup_s", 0.0);
  if (j.contains("upload")) r.upload = phase_from_json(j["upload"]);
  if (j.contains("evaluate")) r.evaluate = phase_from_json(j["evaluate"]);
  if (j.contains("read_back")) r.read_back = phase_from_json(j["read_back"]);
  if (j.contains("end_to_end")) r.end_to_end = phase_from_json(j["end_to_end"]);
  if (j.contains("device_evaluate_median_s"))
    r.device_evaluate_median_s = j["device_evaluate_median_s"].get<double>();
  if (j.contains("device_phase_median_s"))
    r.device_phase_median_s = j["device_phase_median_s"].get<std::map<std::string, double>>();
  r.throughput_pts_per_s = j.value("throughput_pts_per_s", 0.0);
  if (j.contains("accuracy") && j["accuracy"].is_object())
    r.accuracy = accuracy_from_json(j["accuracy"]);
  if (j.contains("extra_phases") && j["extra_phases"].is_object())
    for (const auto& [name, stats] : j["extra_phases"].items())
      r.extra_phases[name] = phase_from_json(stats);
  if (j.contains("figures") && j["figures"].is_object())
    for (const auto& [name, value] : j["figures"].items())
      r.figures[name] =
          value.is_null() ? std::numeric_limits<double>::infinity() : value.get<double>();
  if (!parse_status(j.value("status", "failed"), r.status)) r.status = Status::failed;
  r.reason = j.value("reason", "");
  r.trimming = j.value("trimming", "");
  if (j.contains("library") && j["library"].is_object()) {
    r.library = j["library"].value("path", "");
    r.library_sha256 = j["library"].value("sha256", "");
  }
  return r;
}

std::string csv_header() {
  return "scene,strategy,device,precision,sampling,samples,points,setup_s,upload_median_s,"
         "evaluate_min_s,evaluate_median_s,evaluate_max_s,readback_median_s,end_to_end_median_s,"
         "throughput_pts_per_s,max_abs,rms_abs,max_rel,max_ulp,status,reason,trimming,trim_band,"
         "trim_inside_samples,trim_boundary_samples,trim_misclassified,trim_misclassified_rate";
}

std::string csv_row(const Record& r) {
  const bool measured = r.status == Status::ok;
  auto number = [measured](double x) { return measured ? fmt::format("{}", x) : std::string(); };
  auto accuracy = [&](double Accuracy::*metric) {
    return r.accuracy ? number((*r.accuracy).*metric) : std::string();
  };
  std::array<std::string, 5> trim{};  // the trim columns after `trimming`, in csv_header's order
  if (r.accuracy && r.accuracy->trim) {
    const TrimAccuracy& t = *r.accuracy->trim;
    auto count = [&](std::size_t n) { return measured ? fmt::format("{}", n) : std::string(); };
    trim = {number(t.band), count(t.inside), count(t.boundary),
            t.misclassified ? count(*t.misclassified) : "",
            t.misclassified_rate ? number(*t.misclassified_rate) : ""};
  }
  return fmt::format(
      "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
      csv_text(r.scene), csv_text(r.strategy), csv_text(r.device.name), r.precision, r.sampling,
      r.samples, r.points, number(r.setup_s), number(r.upload.median_s), number(r.evaluate.min_s),
      number(r.evaluate.median_s), number(r.evaluate.max_s), number(r.read_back.median_s),
      number(r.end_to_end.median_s), number(r.throughput_pts_per_s), accuracy(&Accuracy::max_abs),
      accuracy(&Accuracy::rms_abs), accuracy(&Accuracy::max_rel), accuracy(&Accuracy::max_ulp),
      to_string(r.status), csv_text(r.reason), r.trimming, trim[0], trim[1], trim[2], trim[3],
      trim[4]);
}

}  // namespace nurbs
