// The side files a results set may carry beside its results.json, or alone in a folder of their
// own (load_result_sets, harness/report/report.h): lod.json
// (`nurbsbench lod`), camera_path.json (`nurbsbench camera-path`) and memory.json (`nurbsbench
// memory --json`). One type per file, written by its verb through to_json and read back by the
// report through read_*_file, so a field the writer renames breaks the build, not the report.
//
// Reading is strict: a missing or mistyped field is an InputError naming the file, the field (with
// its row index) and the value. The fields a format gained after its /1 files were committed are
// std::optional (absent in older files, shown "n/a" by the report); every other field is required.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace nurbs {

inline constexpr const char* kLodFileFormat = "nurbsbench-lod/1";
inline constexpr const char* kCameraPathFileFormat = "nurbsbench-camera-path/1";
inline constexpr const char* kMemoryFileFormat = "nurbsbench-memory/1";

struct SideDevice {
  std::string name, kind;
};

// ------------------------------------------------------------------------------------- lod.json
struct LodDrawFields {  // one grid drawn from its texture (added after lod/1's first files)
  double render_s = 0;
  std::int64_t index_elements = 0, drawn_pixels = 0;
};
struct LodLevelRow {
  int level = 0;
  std::string samples;  // "64x64"
  double max_distance = 0, max_ulp = 0;
  std::optional<LodDrawFields> draw;
};
struct LodRow {
  std::string scene, samples;
  SideDevice device;
  int repetitions = 0;
  double coarser_by_haar_s = 0, coarser_by_reevaluation_s = 0;
  double finer_by_haar_s = 0, finer_by_reevaluation_s = 0;
  // 002's full baseline (evaluate + read back + upload + index rebuild): added after lod/1.
  std::optional<double> coarser_by_full_reevaluation_s, finer_by_full_reevaluation_s;
  std::optional<std::int64_t> coarser_index_elements, finer_index_elements;
  std::optional<LodDrawFields> draw;  // the evaluated grid's own draw (level 0)
  std::vector<LodLevelRow> levels;
};
struct LodFile {
  nlohmann::json machine = nlohmann::json::object();  // machine_record() (harness/machine.h)
  nlohmann::json settings = nlohmann::json::object();
  std::vector<LodRow> rows;
};

// ----------------------------------------------------------------------------- camera_path.json
struct CameraCounts {
  std::uint64_t draws = 0, passes = 0, host_read_backs = 0, device_copies = 0;
};
struct CameraFrame {
  int frame = 0;
  double distance = 0;
  std::array<double, 3> eye{};
  std::vector<std::array<int, 2>> lod_grids;  // per surface (nu, nv)
  std::uint64_t lod_samples = 0, lod_triangles = 0;
  double lod_frame_s = 0;
  std::uint64_t fixed_samples = 0, fixed_triangles = 0;
  double fixed_frame_s = 0;
};
struct CameraPathRow {
  std::string scene;
  std::uint64_t surfaces = 0;
  SideDevice device;
  std::array<double, 3> centre{}, target{}, up{};
  double radius = 0;
  double median_lod_frame_s = 0, median_fixed_frame_s = 0;
  CameraCounts lod_counts, fixed_counts;
  std::vector<CameraFrame> frames;
};
struct CameraPathFile {
  nlohmann::json machine = nlohmann::json::object();
  // The verb's options as run; the report reads fixed_samples ("64x64") from it.
  nlohmann::json settings = nlohmann::json::object();
  std::vector<CameraPathRow> rows;
  std::string fixed_samples() const;
};

// ---------------------------------------------------------------------------------- memory.json
struct MemoryFileRow {
  std::string scene;
  std::uint64_t surfaces = 0, ksquads = 0, bezier_patches = 0;
  std::uint64_t nurbs_control_points = 0, nurbs_bytes = 0;
  std::uint64_t bezier_control_points = 0, bezier_bytes = 0;
  std::optional<double> ratio;
  // The shared-once count: added after memory/1's first files.
  std::optional<std::uint64_t> bezier_shared_control_points, bezier_shared_bytes;
  std::optional<double> shared_ratio;
};
struct MemoryFile {
  // The file's notes on what is counted (control_point_format, knots_counted, ...), as written.
  nlohmann::json notes = nlohmann::json::object();
  std::vector<MemoryFileRow> rows;
};

void to_json(nlohmann::json& j, const SideDevice& d);
void to_json(nlohmann::json& j, const LodDrawFields& d);
void to_json(nlohmann::json& j, const LodLevelRow& r);
void to_json(nlohmann::json& j, const LodRow& r);
void to_json(nlohmann::json& j, const LodFile& f);
void to_json(nlohmann::json& j, const CameraCounts& c);
void to_json(nlohmann::json& j, const CameraFrame& f);
void to_json(nlohmann::json& j, const CameraPathRow& r);
void to_json(nlohmann::json& j, const CameraPathFile& f);
void to_json(nlohmann::json& j, const MemoryFileRow& r);
void to_json(nlohmann::json& j, const MemoryFile& f);

// Reads a side file strictly (see above); `path` names it in errors. InputError for anything
// malformed, including a format other than the type's.
LodFile read_lod_file(const std::filesystem::path& path);
CameraPathFile read_camera_path_file(const std::filesystem::path& path);
MemoryFile read_memory_file(const std::filesystem::path& path);

}  // namespace nurbs
