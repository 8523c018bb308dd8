// The labels of series and sets: the strategy, and the precision and machine only where a report
// holds several (used by every section that draws a chart).
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <functional>
#include <map>
#include <set>

#include "harness/report/kit.h"

namespace nurbs::report {

// Labels name the strategy; the precision and the machine only where the report holds more than
// one of them, so a single run's chart reads "cpu-tensor", not "cpu-tensor f32 [NVIDIA H200]".
// A machine is its CPU model, core count and GPUs: the sets of one machine (each a directory
// named after its chart, the same name on every machine) are one series, another machine's the
// series beside it. glsl-deboor's instanced draw mode (device detail "draw") and vk-ksquad's
// mappings other than uniform (detail "vk_mode") are series of their own beside the default, so
// a chart shows each where several were measured.
class Labeller {
 public:
  explicit Labeller(const std::vector<ResultSet>& sets) {
    std::set<std::string> precisions;
    // Per machine: its GPUs, else the CPU, named as briefly as still tells the machines apart.
    struct Machine {
      std::string gpus, cpu, full_cpu, cores;
    };
    std::map<std::string, Machine> machines;
    std::map<const ResultSet*, std::string> key_of;
    for (const ResultSet& s : sets) {
      for (const Record& r : s.results.records) precisions.insert(r.precision);
      Machine m;
      m.full_cpu = machine_value<std::string>(s, "cpu_model", "unknown CPU");
      m.cpu = short_cpu_model(m.full_cpu);
      const int cores = machine_value<int>(s, "logical_cores", machine_value<int>(s, "threads", 0));
      m.cores = cores > 0 ? fmt::format(" {}t", cores) : "";
      m.gpus = fmt::format("{}", fmt::join(gpus_of(s), " + "));
      const std::string key = m.full_cpu + "|" + m.cores + "|" + m.gpus;
      machines.emplace(key, m);
      key_of[&s] = key;
    }
    by_precision_ = precisions.size() > 1;
    if (machines.size() < 2) return;
    const std::vector<std::function<std::string(const Machine&)>> levels = {
        [](const Machine& m) { return m.gpus.empty() ? m.cpu + m.cores : m.gpus; },
        [](const Machine& m) { return (m.gpus.empty() ? "" : m.gpus + ", ") + m.cpu + m.cores; },
        [](const Machine& m) {
          return (m.gpus.empty() ? "" : m.gpus + ", ") + m.full_cpu + m.cores;
        }};
    for (const auto& level : levels) {
      std::set<std::string> labels;
      for (const auto& [key, m] : machines) labels.insert(level(m));
      if (labels.size() < machines.size() && &level != &levels.back()) continue;
      for (const auto& [set, key] : key_of) machine_[set] = level(machines.at(key));
      break;
    }
  }
  std::string operator()(const Row& row) const {
    std::string label = row.record->strategy;
    const auto draw = row.record->device.details.find("draw");
    if (draw != row.record->device.details.end() && draw->second == "instanced")
      label += " (instanced)";
    // vk-ksquad's mappings of 003 §4 (uniform, the default, is unlabelled), and where the
    // adaptive test's corners were evaluated when it is the host.
    const auto mode = row.record->device.details.find("vk_mode");
    if (mode != row.record->device.details.end() && mode->second != "uniform") {
      const auto corners = row.record->device.details.find("vk_corners");
      const bool host = corners != row.record->device.details.end() && corners->second == "host";
      label += " (" + mode->second + (host ? ", host corners" : "") + ")";
    }
    if (by_precision_) label += " " + row.record->precision;
    return label + machine_suffix(*row.set);
  }
  // The machine a set was measured on, "" where the report holds one machine.
  std::string machine(const ResultSet& set) const {
    const auto it = machine_.find(&set);
    return it == machine_.end() ? "" : it->second;
  }
  std::string machine_suffix(const ResultSet& set) const {
    const std::string m = machine(set);
    return m.empty() ? "" : " [" + m + "]";
  }
  // A set in a table of several sets: its directory's name, and its machine where there are
  // several (each machine's sets carry the same directory names).
  std::string set_name(const ResultSet& set) const { return set.tag + machine_suffix(set); }
  // What tells a set's rows of a side file apart from other sets' (several sets): the machine,
  // or the set's name where another set of that machine holds the same file too.
  std::string side_suffix(const ResultSet& set, const std::vector<ResultSet>& sets,
                          const std::function<bool(const ResultSet&)>& has) const {
    if (sets.size() < 2) return "";
    const std::string m = machine(set);
    const bool shared = std::any_of(sets.begin(), sets.end(), [&](const ResultSet& other) {
      return &other != &set && has(other) && machine(other) == m;
    });
    if (m.empty() || shared) return " [" + set.tag + (m.empty() ? "" : ", " + m) + "]";
    return " [" + m + "]";
  }

 private:
  bool by_precision_ = false;
  std::map<const ResultSet*, std::string> machine_;  // empty: one machine
};

}  // namespace nurbs::report
