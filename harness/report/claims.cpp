#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

// ---------------------------------------------------------------------------- paper vs measured

// One configuration where both sides of a claim were measured. `fast` is the side the paper says
// is faster; the measured factor is slow_s / fast_s.
struct Comparison {
  std::string where;  // "patch144 2048x2048"
  std::string fast_name, slow_name;
  double fast_s = 0, slow_s = 0;
  DeviceInfo fast_device, slow_device;
  std::string directory;  // the results set the times come from
  // The fast side's time on its smallest workload in the same set: its fixed cost per evaluation
  // (draw calls, dispatches, transfers); NaN when the data have no smaller workload.
  double fixed_s = std::numeric_limits<double>::quiet_NaN();
  std::size_t fixed_points = 0;
  std::size_t fast_surfaces = 0, fixed_surfaces = 0;
};

// Which device a comparison's verdict speaks of: a real GPU on either side, by name (the side the
// paper says is slower is the GPU in some claims), or else the CPU, where the host and the software
// stand-ins for a GPU API are one group, as all of them are CPU figures. The rank orders a claim's
// rows: GPUs first.
struct DeviceGroup {
  int rank = 0;
  std::string name;
  auto operator<=>(const DeviceGroup&) const = default;
};
DeviceGroup device_group(const Comparison& c) {
  for (const DeviceInfo* d : {&c.fast_device, &c.slow_device})
    if (d->kind == "gpu") return {0, "GPU: " + gpu_name(*d)};
  const DeviceInfo& fast = c.fast_device;
  if (fast.kind == "cpu") return {1, "CPU"};
  if (fast.kind.empty() || fast.kind == "n/a") return {3, "unknown device"};
  return {2, fmt::format("{}: {}", fast.kind, fast.name.empty() ? "unknown device" : fast.name)};
}
// The CPU group names the stand-ins that ran in it, so a reader sees which drivers the verdict is
// about.
std::string group_label(const DeviceGroup& group, const std::vector<Comparison>& cs) {
  if (group.name != "CPU") return group.name;
  std::set<std::string> stand_ins;
  for (const Comparison& c : cs)
    for (const DeviceInfo* d : {&c.fast_device, &c.slow_device})
      if (software_device(*d)) stand_ins.insert(stand_in_name(*d));
  if (stand_ins.empty()) return "CPU (host)";
  return fmt::format("CPU stand-in ({})", fmt::join(stand_ins, ", "));
}

using Compare = std::function<std::vector<Comparison>(const std::vector<ResultSet>&)>;

struct Claim {
  std::string paper, figure, quote;
  std::string chart;        // the chart whose command makes the data
  std::string measured_as;  // which records, which ratio
  double factor = 1;        // holds when the (geometric mean) slow / fast >= factor
  std::string factor_text;  // why that factor is the claim's
  Compare compare;
};

enum class Pick { largest, smallest, each };

// Per (set, scene, samples) kept where both sides have an ok record: the fastest strategy of each
// side by `time`, so a side is the paper's method at its best here; `pick` chooses which of those
// configurations (by the fast record's points) the claim speaks of.
Compare records_compared(std::vector<std::string> fast, std::vector<std::string> slow,
                         std::function<bool(const Record&)> keep,
                         std::function<double(const Record&)> time, Pick pick) {
  return [=](const std::vector<ResultSet>& sets) {
    const auto rows = rows_where(sets, [&](const Record& r) { return keep(r) && time(r) > 0; });
    const auto fastest = [&](const std::vector<std::string>& names, const Row& like) {
      const Record* best = nullptr;
      for (const Row& r : rows)
        if (r.set == like.set && r.record->scene == like.record->scene &&
            r.record->samples == like.record->samples &&
            std::find(names.begin(), names.end(), r.record->strategy) != names.end() &&
            (!best || time(*r.record) < time(*best)))
          best = r.record;
      return best;
    };
    std::map<std::tuple<const ResultSet*, std::string, std::string>, Comparison> found;
    std::map<std::tuple<const ResultSet*, std::string, std::string>, std::size_t> points;
    for (const Row& r : rows) {
      const auto key = std::make_tuple(r.set, r.record->scene, r.record->samples);
      if (found.contains(key)) continue;
      const Record* f = fastest(fast, r);
      const Record* s = fastest(slow, r);
      if (!f || !s) continue;
      Comparison c{r.record->scene + " " + r.record->samples,
                   f->strategy,
                   s->strategy,
                   time(*f),
                   time(*s),
                   f->device,
                   s->device,
                   r.set->directory.string()};
      const Record* smallest = nullptr;
      for (const Row& o : rows)
        if (o.set == r.set && o.record->strategy == f->strategy &&
            (!smallest || o.record->points < smallest->points))
          smallest = o.record;
      if (smallest && smallest->points < f->points) {
        c.fixed_s = time(*smallest);
        c.fixed_points = smallest->points;
        c.fast_surfaces = f->surfaces;
        c.fixed_surfaces = smallest->surfaces;
      }
      found.emplace(key, c);
      points.emplace(key, f->points);
    }
    std::vector<Comparison> out;
    if (found.empty()) return out;
    if (pick == Pick::each) {
      for (const auto& [key, c] : found) out.push_back(c);
      return out;
    }
    // Per device group: each verdict speaks of its own device's largest (smallest) workload, not
    // of whichever machine measured the largest one.
    std::map<DeviceGroup, decltype(found)::const_iterator> chosen;
    for (auto it = found.cbegin(); it != found.cend(); ++it) {
      const auto [at, inserted] = chosen.try_emplace(device_group(it->second), it);
      if (!inserted && (pick == Pick::largest ? points[it->first] > points[at->second->first]
                                              : points[it->first] < points[at->second->first]))
        at->second = it;
    }
    for (const auto& [group, it] : chosen) out.push_back(it->second);
    return out;
  };
}

// 002 Fig 15 from lod.json: each LOD change (coarser, finer) by Haar against re-evaluation as the
// paper's baseline pays it (read-back, vertex upload and index rebuild included), or, in files
// from before that was measured, the de Boor passes alone.
std::vector<Comparison> lod_compared(const std::vector<ResultSet>& sets) {
  std::vector<Comparison> out;
  for (const ResultSet& set : sets) {
    if (!set.lod) continue;
    for (const LodRow& row : set.lod->rows) {
      const DeviceInfo device{row.device.name, row.device.kind, {}};
      for (const bool coarser : {true, false}) {
        const char* way = coarser ? "coarser" : "finer";
        const double haar = coarser ? row.coarser_by_haar_s : row.finer_by_haar_s,
                     full = or_nan(coarser ? row.coarser_by_full_reevaluation_s
                                           : row.finer_by_full_reevaluation_s),
                     again = full > 0 ? full
                                      : (coarser ? row.coarser_by_reevaluation_s
                                                 : row.finer_by_reevaluation_s);
        if (!(haar > 0) || !(again > 0)) continue;
        out.push_back({fmt::format("{} {} {}", row.scene, row.samples, way), "Haar",
                       full > 0 ? "full re-evaluation" : "re-evaluation (de Boor passes alone)",
                       haar, again, device, device, set.directory.string()});
      }
    }
  }
  return out;
}

bool on_patch144_grid(const Record& r) {
  return is_measurement(r) && r.scene == "patch144" && r.sampling == "grid";
}
double evaluate_time(const Record& r) {
  return r.evaluate.median_s;
}

std::vector<Claim> paper_claims() {
  const std::vector<std::string> pingpong = {"gl-pingpong", "gl-pingpong-packed"},
                                 coxdeboor = {"cpu-coxdeboor"};
  const auto frame_time = [](const Record& r) { return r.extra_phases.at("frame").median_s; };
  return {
      {"000 Krishnamurthy 2007", "Fig 7",
       "The GPU-based evaluation is faster than the CPU-based evaluation by a factor of about 50 "
       "when evaluated at a large numbers of evaluation points.",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (the CPU evaluation) / "
       "the faster of gl-pingpong, gl-pingpong-packed (000's method)",
       10, "≥ 10× (about 50×; 10× on the paper's slowest card)",
       records_compared(pingpong, coxdeboor, on_patch144_grid, evaluate_time, Pick::largest)},
      {"000 Krishnamurthy 2007", "Fig 7",
       "the GPU evaluation has more overhead for very small patches and hence is not suitable for "
       "evaluating surfaces having less than 16 evaluation points.",
       "fig7_time_vs_points",
       "patch144, smallest grid measured (at most 16 points): evaluate median of the faster of "
       "gl-pingpong, gl-pingpong-packed / cpu-coxdeboor",
       1, "> 1× (the CPU is faster)",
       records_compared(
           coxdeboor, pingpong,
           [](const Record& r) { return on_patch144_grid(r) && r.points <= 16; }, evaluate_time,
           Pick::smallest)},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_many_surfaces",
       "many-N at 16x16 per surface (untrimmed; the paper trims one third), largest N measured: "
       "end_to_end median (upload + evaluate + read back, one frame) of glu-nurbs / the faster of "
       "gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (40-50×)",
       records_compared(
           pingpong, {"glu-nurbs"},
           [](const Record& r) {
             return is_measurement(r) && numbered_scene(r.scene, "many-") && r.samples == "16x16";
           },
           [](const Record& r) { return r.end_to_end.median_s; }, Pick::largest)},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_trimmed_ducks",
       "many-ducks-N at 16x16 per surface, one third trimmed as in the paper, largest N measured: "
       "frame time (evaluate + classify + draw, as the trimmed Fig 8 section) of glu-nurbs / the "
       "faster of gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (40-50×)",
       records_compared(
           pingpong, {"glu-nurbs"},
           [](const Record& r) {
             return is_measurement(r) && numbered_scene(r.scene, "many-ducks-") &&
                    r.samples == "16x16";
           },
           trimmed_frame_s, Pick::largest)},
      {"002 Tan 2012", "Fig 14",
       "The figure shows that our method promotes the evaluation speed orders of magnitude.",
       "fig14_deboor_vs_basis",
       "tan16, tan64, tan256 at 256x256: evaluate median of the faster of gl-pingpong, "
       "gl-pingpong-packed (the basis passes of [7]) / glsl-deboor, per scene",
       10, "≥ 10× (one order of magnitude, the least \"orders\" can mean)",
       records_compared(
           {"glsl-deboor"}, pingpong,
           [](const Record& r) {
             return is_measurement(r) && r.samples == "256x256" &&
                    (r.scene == "tan16" || r.scene == "tan64" || r.scene == "tan256");
           },
           evaluate_time, Pick::each)},
      {"002 Tan 2012", "Fig 15",
       "The figure shows that rendering with wavelet transform is 3-5 times faster than "
       "re-evaluation",
       "fig15_lod",
       "lod.json, tan21x23 at each size: median time of one LOD change by re-evaluation (the "
       "paper's baseline: evaluate, read back, upload the vertices, rebuild the index buffer; "
       "the de Boor passes alone in files without it) / by Haar, coarser and finer",
       3, "≥ 3× (3-5×)", lod_compared},
      {"003 RPNS 2014", "§1, §6 (the pipelines of Fig 3)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median (update + evaluate) of "
       "cpu-bezier (decomposition redone every frame) / the faster of vk-ksquad, cl-stair, per "
       "scene",
       100, "≥ 100× (several orders of magnitude)",
       records_compared({"vk-ksquad", "cl-stair"}, {"cpu-bezier"}, is_frame_measurement, frame_time,
                        Pick::each)},
      {"003 RPNS 2014", "§1, §6 (like for like: the baseline tessellated on the GPU)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median (update + evaluate) of "
       "vk-bezier (decomposition on the CPU and upload every frame, Bézier patches tessellated in "
       "vk-ksquad's pipeline shape) / vk-ksquad, per scene",
       100, "≥ 100× (several orders of magnitude)",
       records_compared({"vk-ksquad"}, {"vk-bezier"}, is_frame_measurement, frame_time,
                        Pick::each)},
      {"004 Macri 1999", "no figure (Tessellation; Optimizations)",
       "To speed up the calculation of S(u,v), we can calculate Bi,p(u) and Bj,q(v) at the "
       "subdivision points and store these in an array. [...] we can achieve better performance "
       "by using the new Streaming SIMD Extensions",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (basis functions per "
       "point) / the faster of cpu-tensor (basis tables, SIMD), cpu-horner (power basis, SIMD)",
       1, "> 1× (any speed-up)",
       records_compared({"cpu-tensor", "cpu-horner"}, coxdeboor, on_patch144_grid, evaluate_time,
                        Pick::largest)},
  };
}

// The reasoning rule: what in the measurements explains a claim that does not hold, and what
// qualifies one that does. Each cause is read from the records, never written per claim.
std::vector<std::string> measured_causes(const std::vector<Comparison>& cs, bool holds) {
  std::vector<std::string> causes;
  std::set<std::string> software, differ;
  const Comparison* worst_fixed = nullptr;
  for (const Comparison& c : cs) {
    if (software_device(c.fast_device)) software.insert(c.fast_device.name);
    // Two host-CPU sides on different thread counts: the factor is partly the threads'.
    if (c.fast_device.kind == "cpu" && c.slow_device.kind == "cpu" &&
        !software_device(c.fast_device) && !software_device(c.slow_device) &&
        c.fast_device.name != c.slow_device.name)
      differ.insert(fmt::format("{} on {} vs {} on {}", c.fast_name, c.fast_device.name,
                                c.slow_name, c.slow_device.name));
    if (std::isfinite(c.fixed_s) &&
        (!worst_fixed || c.fixed_s / c.fast_s > worst_fixed->fixed_s / worst_fixed->fast_s))
      worst_fixed = &c;
  }
  if (!holds && !software.empty())
    causes.push_back(fmt::format(
        "the side claimed faster ran on {}, recorded as device kind \"cpu\": a CPU rasterizer "
        "or compute driver stands in for the GPU, so a CPU figure is compared with a CPU figure",
        fmt::join(software, ", ")));
  // A fixed cost per evaluation (draw calls, passes, dispatches) above a fifth of the time is
  // what keeps a parallel device from its throughput.
  if (!holds && worst_fixed && worst_fixed->fixed_s / worst_fixed->fast_s >= 0.2)
    causes.push_back(fmt::format(
        "{}'s fixed cost per evaluation, its time on its smallest workload ({} points: {}), is "
        "{:.0f}% of its time at {}",
        worst_fixed->fast_name, worst_fixed->fixed_points, seconds_text(worst_fixed->fixed_s),
        std::min(100.0, 100 * worst_fixed->fixed_s / worst_fixed->fast_s), worst_fixed->where));
  // Time that grows with the surfaces at no less than half its cost per surface on the smallest
  // workload is paid per surface (a draw, a pass, a dispatch each), not per point.
  for (const Comparison& c : cs)
    if (!holds && std::isfinite(c.fixed_s) && c.fixed_surfaces > 0 &&
        c.fast_surfaces > c.fixed_surfaces &&
        c.fast_s / static_cast<double>(c.fast_surfaces) >=
            0.5 * c.fixed_s / static_cast<double>(c.fixed_surfaces))
      causes.push_back(fmt::format(
          "{}'s time is paid per surface (per draw): {} per surface at {} ({} surfaces), {} on "
          "its smallest workload ({} surface{})",
          c.fast_name, seconds_text(c.fast_s / static_cast<double>(c.fast_surfaces)), c.where,
          c.fast_surfaces, seconds_text(c.fixed_s / static_cast<double>(c.fixed_surfaces)),
          c.fixed_surfaces, c.fixed_surfaces == 1 ? "" : "s"));
  if (!differ.empty())
    causes.push_back(
        fmt::format("the sides ran on different devices: {}", fmt::join(differ, "; ")));
  if (!holds && causes.empty()) causes.push_back("no cause found in these records");
  return causes;
}

std::string factor_text(double ratio) {
  const std::string text = report_number(ratio) + "×";
  return ratio < 1 ? fmt::format("{} ({}× the other way)", text, report_number(1 / ratio)) : text;
}

ReportSection claims_section(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  ReportSection s;
  s.id = in.row.id;
  s.title = in.row.title;
  s.context = context_of({}, sets);
  ReportTable table{
      "",
      {"paper", "figure", "claim (quoted)", "measured as", "holds when", "measured on", "measured",
       "holds?", "why (from the measurements)", "command that made the data"},
      {}};
  for (const Claim& claim : paper_claims()) {
    const std::vector<Comparison> all = claim.compare(sets);
    const std::string& run = chart_run(claim.chart);
    const std::vector<std::string> head{claim.paper, claim.figure, claim.quote, claim.measured_as,
                                        claim.factor_text};
    if (all.empty()) {
      std::vector<std::string> row = head;
      row.insert(row.end(), {"-", "-", "not measured", "these results have no records for it",
                             regenerate(run, sets)});
      table.rows.push_back(std::move(row));
      continue;
    }
    // A GPU and a CPU stand-in for it answer different questions: one verdict per device.
    std::map<DeviceGroup, std::vector<Comparison>> groups;
    for (const Comparison& c : all) groups[device_group(c)].push_back(c);
    for (const auto& [group, cs] : groups) {
      double log_sum = 0;
      std::vector<std::string> each;
      for (const Comparison& c : cs) {
        const double ratio = c.slow_s / c.fast_s;
        log_sum += std::log(ratio);
        each.push_back(fmt::format("{}: {} {} / {} {} = {}", c.where, c.slow_name,
                                   seconds_text(c.slow_s), c.fast_name, seconds_text(c.fast_s),
                                   factor_text(ratio)));
      }
      const double ratio = std::exp(log_sum / static_cast<double>(cs.size()));
      const bool holds = ratio >= claim.factor && (claim.factor > 1 || ratio > 1);
      std::string measured = fmt::format("{}", fmt::join(each, "; "));
      if (cs.size() > 1)
        measured =
            fmt::format("{} (geometric mean of {}): {}", factor_text(ratio), cs.size(), measured);
      std::vector<std::string> row = head;
      row.insert(row.end(), {group_label(group, cs), measured, holds ? "holds" : "does not hold",
                             fmt::format("{}", fmt::join(measured_causes(cs, holds), "; ")),
                             regenerate_in(run, cs.front().directory)});
      table.rows.push_back(std::move(row));
    }
  }
  s.tables.push_back(std::move(table));
  s.notes.push_back(
      "measured = the slow side's median time over the fast side's (the side the paper says is "
      "faster), in the configurations named; a side of several strategies is the fastest of "
      "them there, the paper's method at its best on this machine. Several configurations are "
      "summarised by their geometric mean.");
  s.notes.push_back(
      "Verdicts are per device: a claim has a row for each GPU its comparisons ran on (by name; a "
      "comparison with a GPU on either side is that GPU's) and one for the CPU (the host CPU and "
      "the software stand-ins for a GPU API, llvmpipe, lavapipe and PoCL, whose figures are all "
      "CPU figures), each with its own configurations, geometric mean and causes.");
  return s;
}

}  // namespace nurbs::report
