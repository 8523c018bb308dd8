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
  std::string factor_text;  // why that factor is the claim's: the paper's own number
  Compare compare;
  std::string clock;  // which clock the times are read from, and why that one
};

// The verdict classes for a paper's factor: "holds" at the paper's number; "holds within 2x"
// from half of it (a machine, driver or card generation apart is not a refutation, and the
// papers' own figures spread that much across their cards); below that "does not hold". A claim
// of any speed-up (factor 1) has no middle class.
std::string verdict(double ratio, double factor) {
  if (ratio >= factor && (factor > 1 || ratio > 1)) return "holds";
  if (factor > 1 && ratio >= factor / 2) return "holds within 2×";
  return "does not hold";
}

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

// 002 Fig 15 from lod.json: each LOD change (coarser, finer) by Haar against re-evaluation.
// `on_device`: the re-evaluation that stays on the device (the de Boor passes alone), as the Haar
// side stays there; otherwise re-evaluation as a renderer with its mesh on the host pays it
// (read-back, vertex upload and index rebuild included), in files that measured it.
Compare lod_compared(bool on_device) {
  return [on_device](const std::vector<ResultSet>& sets) {
    std::vector<Comparison> out;
    for (const ResultSet& set : sets) {
      if (!set.lod) continue;
      for (const LodRow& row : set.lod->rows) {
        const DeviceInfo device{row.device.name, row.device.kind, {}};
        for (const bool coarser : {true, false}) {
          const char* way = coarser ? "coarser" : "finer";
          const double haar = coarser ? row.coarser_by_haar_s : row.finer_by_haar_s,
                       again = on_device ? (coarser ? row.coarser_by_reevaluation_s
                                                    : row.finer_by_reevaluation_s)
                                         : or_nan(coarser ? row.coarser_by_full_reevaluation_s
                                                          : row.finer_by_full_reevaluation_s);
          if (!(haar > 0) || !(again > 0)) continue;
          out.push_back({fmt::format("{} {} {}", row.scene, row.samples, way), "Haar",
                         on_device ? "re-evaluation on the device" : "full re-evaluation", haar,
                         again, device, device, set.directory.string()});
        }
      }
    }
    return out;
  };
}

bool on_patch144_grid(const Record& r) {
  return is_measurement(r) && r.scene == "patch144" && r.sampling == "grid";
}
double evaluate_time(const Record& r) {
  return r.evaluate.median_s;
}
// The device's own time for evaluate where the record has it (GL GL_TIME_ELAPSED, Vulkan
// timestamps, OpenCL profiling), else the wall clock's.
double device_evaluate_time(const Record& r) {
  return r.device_evaluate_median_s ? *r.device_evaluate_median_s : r.evaluate.median_s;
}
// A deforming frame as a renderer pays it with the points staying on the device: the control
// points' update, the evaluation and the classification; the read-back the frame phase also holds
// is left out.
double frame_on_device_s(const Record& r) {
  double s = r.upload.median_s + r.evaluate.median_s;
  if (auto it = r.extra_phases.find("classify"); it != r.extra_phases.end())
    s += it->second.median_s;
  return s;
}

std::vector<Claim> paper_claims() {
  const std::vector<std::string> pingpong = {"gl-pingpong", "gl-pingpong-packed"},
                                 coxdeboor = {"cpu-coxdeboor"};
  const auto frame_time = [](const Record& r) { return r.extra_phases.at("frame").median_s; };
  const auto many_at_16 = [](const Record& r) {
    return is_measurement(r) && numbered_scene(r.scene, "many-") && r.samples == "16x16";
  };
  const char* wall = "host wall clock around each call (both sides)";
  return {
      {"000 Krishnamurthy 2007", "Fig 7",
       "The GPU-based evaluation is faster than the CPU-based evaluation by a factor of about 50 "
       "when evaluated at a large numbers of evaluation points.",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (the CPU evaluation) / "
       "the faster of gl-pingpong, gl-pingpong-packed (000's method)",
       50, "≥ 50× (\"about 50\"; within 2×: ≥ 25×)",
       records_compared(pingpong, coxdeboor, on_patch144_grid, evaluate_time, Pick::largest),
       "host wall clock around evaluate, which returns when the device is done: the paper times "
       "the evaluation as its program waits for it"},
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
           Pick::smallest),
       "host wall clock: the claim is about the overhead the host pays per call"},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_many_surfaces",
       "many-N at 16x16 per surface (untrimmed; the paper trims one third), largest N measured: "
       "frame time from data already on the device (evaluate + draw where the strategy draws) of "
       "glu-nurbs / the faster of gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (\"40-50 times\"; within 2×: ≥ 20×)",
       records_compared(pingpong, {"glu-nurbs"}, many_at_16, trimmed_frame_s, Pick::largest),
       "host wall clock around the frame's phases; the surfaces are uploaded once, as the paper "
       "draws every frame from data on the GPU"},
      {"000 Krishnamurthy 2007", "Fig 8, end to end (another question: the points on the host)",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_many_surfaces",
       "many-N at 16x16 per surface, largest N measured: end_to_end median (upload + evaluate + "
       "read back) of glu-nurbs / the faster of gl-pingpong, gl-pingpong-packed: what a product "
       "that needs the points on the host would pay, not what the paper measured",
       40, "≥ 40× (the paper's factor, for comparison)",
       records_compared(
           pingpong, {"glu-nurbs"}, many_at_16,
           [](const Record& r) { return r.end_to_end.median_s; }, Pick::largest),
       wall},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_trimmed_ducks",
       "many-ducks-N at 16x16 per surface, one third trimmed as in the paper, largest N measured: "
       "frame time (evaluate + classify + draw, as the trimmed Fig 8 section) of glu-nurbs / the "
       "faster of gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (\"40-50 times\"; within 2×: ≥ 20×)",
       records_compared(
           pingpong, {"glu-nurbs"},
           [](const Record& r) {
             return is_measurement(r) && numbered_scene(r.scene, "many-ducks-") &&
                    r.samples == "16x16";
           },
           trimmed_frame_s, Pick::largest),
       "host wall clock around the frame's phases, from data on the device"},
      {"002 Tan 2012", "Fig 14",
       "The figure shows that our method promotes the evaluation speed orders of magnitude.",
       "fig14_deboor_vs_basis",
       "tan16, tan64, tan256 at 256x256: evaluate median of the faster of gl-pingpong, "
       "gl-pingpong-packed (the basis passes of [7]) / glsl-deboor, per scene",
       10, "≥ 10× (one order of magnitude, the least \"orders\" can mean; within 2×: ≥ 5×)",
       records_compared(
           {"glsl-deboor"}, pingpong,
           [](const Record& r) {
             return is_measurement(r) && r.samples == "256x256" &&
                    (r.scene == "tan16" || r.scene == "tan64" || r.scene == "tan256");
           },
           device_evaluate_time, Pick::each),
       "device timestamps of evaluate (GL_TIME_ELAPSED), wall clock only where a record has "
       "none: both sides are GPU passes, and at 256² the host's cost per call would decide a "
       "wall-clock ratio"},
      {"002 Tan 2012", "Fig 15",
       "The figure shows that rendering with wavelet transform is 3-5 times faster than "
       "re-evaluation",
       "fig15_lod",
       "lod.json, tan21x23 at each size: median time of one LOD change by re-evaluation on the "
       "device (the de Boor passes, the points staying on the device as Haar's do) / by Haar, "
       "coarser and finer",
       3, "≥ 3× (\"3-5 times\"; within 2×: ≥ 1.5×)", lod_compared(true),
       "host wall clock around each LOD change, both sides on the device"},
      {"002 Tan 2012", "Fig 15, through the host (another question: the mesh on the host)",
       "The figure shows that rendering with wavelet transform is 3-5 times faster than "
       "re-evaluation",
       "fig15_lod",
       "lod.json, tan21x23 at each size: median time of one LOD change by full re-evaluation "
       "(evaluate, read back, upload the vertices, rebuild the index buffer) / by Haar, coarser "
       "and finer: a renderer that keeps its mesh on the host, not what the paper measured",
       3, "≥ 3× (the paper's factor, for comparison)", lod_compared(false), wall},
      {"003 RPNS 2014", "§1, §6 (the pipelines of Fig 3)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median from data on the device "
       "(update + evaluate; no read-back) of cpu-bezier (decomposition redone every frame) / the "
       "faster of vk-ksquad, cl-stair, per scene",
       100, "≥ 100× (several orders of magnitude; within 2×: ≥ 50×)",
       records_compared({"vk-ksquad", "cl-stair"}, {"cpu-bezier"}, is_frame_measurement,
                        frame_on_device_s, Pick::each),
       "host wall clock, the sum of the frame's update, evaluate and classify medians; the draw "
       "is not timed in the deforming runs"},
      {"003 RPNS 2014", "§1, §6, end to end (another question: the points on the host)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median (update + evaluate + read "
       "back) of cpu-bezier / the faster of vk-ksquad, cl-stair, per scene: a product that needs "
       "the points on the host, not what the paper measured",
       100, "≥ 100× (the paper's factor, for comparison)",
       records_compared({"vk-ksquad", "cl-stair"}, {"cpu-bezier"}, is_frame_measurement, frame_time,
                        Pick::each),
       wall},
      {"003 RPNS 2014", "§1, §6 (like for like: the baseline tessellated on the GPU)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median from data on the device "
       "(update + evaluate; no read-back) of vk-bezier (decomposition on the CPU and upload every "
       "frame, Bézier patches tessellated in vk-ksquad's pipeline shape) / vk-ksquad, per scene",
       100, "≥ 100× (several orders of magnitude; within 2×: ≥ 50×)",
       records_compared({"vk-ksquad"}, {"vk-bezier"}, is_frame_measurement, frame_on_device_s,
                        Pick::each),
       "host wall clock, the sum of the frame's update, evaluate and classify medians"},
      {"004 Macri 1999", "no figure (Tessellation; Optimizations)",
       "To speed up the calculation of S(u,v), we can calculate Bi,p(u) and Bj,q(v) at the "
       "subdivision points and store these in an array. [...] we can achieve better performance "
       "by using the new Streaming SIMD Extensions",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (basis functions per "
       "point) / the faster of cpu-tensor (basis tables, SIMD), cpu-horner (power basis, SIMD); "
       "each side's threads shown, and the factor per thread where they differ",
       1, "> 1× (any speed-up)",
       records_compared({"cpu-tensor", "cpu-horner"}, coxdeboor, on_patch144_grid, evaluate_time,
                        Pick::largest),
       "host wall clock (both sides on the host CPU)"},
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

// Where both sides ran on the host on different thread counts (a device detail "threads"), the
// factor per thread beside the factor: a 16-thread baseline against a 1-thread one is mostly
// the threads' speed-up, and the paper's claim is the method's.
std::string per_thread_text(const Comparison& c, double ratio) {
  const auto threads = [](const DeviceInfo& d) {
    const std::string text = detail_of(d, "threads");
    int n = 0;
    for (const char ch : text) {
      if (ch < '0' || ch > '9') return 0;
      n = n * 10 + (ch - '0');
      if (n > 100000) return 0;
    }
    return n;
  };
  // A strategy that records no thread count runs on one (cpu-coxdeboor: the papers' baseline).
  const int fast = c.fast_device.kind == "cpu" && !software_device(c.fast_device)
                       ? std::max(1, threads(c.fast_device))
                       : 0;
  const int slow = c.slow_device.kind == "cpu" && !software_device(c.slow_device)
                       ? std::max(1, threads(c.slow_device))
                       : 0;
  if (fast == 0 || slow == 0 || fast == slow) return "";
  return fmt::format(" ({} on {} thread{}, {} on {}: {}× per thread)", c.fast_name, fast,
                     fast == 1 ? "" : "s", c.slow_name, slow, report_number(ratio * slow / fast));
}

// The command that made the set at `directory` (regenerate_set), the chart's declared one where
// the set is not among `sets` (a side file's, such as lod.json's).
std::string command_that_made(const std::string& run, const std::string& directory,
                              const std::vector<ResultSet>& sets) {
  for (const ResultSet& set : sets)
    if (set.directory.string() == directory) return regenerate_set(run, set);
  return regenerate_in(run, directory);
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
      {"paper", "figure", "claim (quoted)", "measured as", "holds when", "clock", "measured on",
       "measured", "holds?", "why (from the measurements)", "command that made the data"},
      {}};
  for (const Claim& claim : paper_claims()) {
    const std::vector<Comparison> all = claim.compare(sets);
    const std::string& run = chart_run(claim.chart);
    const std::vector<std::string> head{claim.paper,       claim.figure,      claim.quote,
                                        claim.measured_as, claim.factor_text, claim.clock};
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
        each.push_back(fmt::format("{}: {} {} / {} {} = {}{}", c.where, c.slow_name,
                                   seconds_text(c.slow_s), c.fast_name, seconds_text(c.fast_s),
                                   factor_text(ratio), per_thread_text(c, ratio)));
      }
      const double ratio = std::exp(log_sum / static_cast<double>(cs.size()));
      const std::string verdict_text = verdict(ratio, claim.factor);
      const bool holds = verdict_text == "holds";
      std::string measured = fmt::format("{}", fmt::join(each, "; "));
      if (cs.size() > 1)
        measured =
            fmt::format("{} (geometric mean of {}): {}", factor_text(ratio), cs.size(), measured);
      std::vector<std::string> row = head;
      row.insert(row.end(), {group_label(group, cs), measured, verdict_text,
                             fmt::format("{}", fmt::join(measured_causes(cs, holds), "; ")),
                             command_that_made(run, cs.front().directory, sets)});
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
      "holds? = \"holds\" at the paper's own factor, \"holds within 2×\" from half of it (a "
      "machine, a driver or a card generation apart: the papers' own figures spread that much "
      "across their cards), else \"does not hold\". Rows marked \"another question\" keep the "
      "end-to-end comparison (the points or the mesh on the host), which the paper did not "
      "measure; their verdict is against the paper's factor for comparison only. clock = which "
      "clock the times are read from.");
  s.notes.push_back(
      "Verdicts are per device: a claim has a row for each GPU its comparisons ran on (by name; a "
      "comparison with a GPU on either side is that GPU's) and one for the CPU (the host CPU and "
      "the software stand-ins for a GPU API, llvmpipe, lavapipe and PoCL, whose figures are all "
      "CPU figures), each with its own configurations, geometric mean and causes.");
  return s;
}

}  // namespace nurbs::report
