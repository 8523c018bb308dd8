#include "strategies/opencl/cl_read_back.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

#include "strategies/host_results.h"

namespace nurbs::opencl {

ReadBackPath read_back_path(const Context& ctx, const StrategyOptions& options) {
  const auto it = options.extra.find("read-back");
  if (it != options.extra.end() && !it->second.empty()) {
    if (it->second == "staged") return ReadBackPath::staged;
    if (it->second == "mapped") return ReadBackPath::mapped;
    throw std::runtime_error("read-back expects 'staged' or 'mapped', got '" + it->second + "'");
  }
  cl_bool unified = CL_FALSE;
  check(clGetDeviceInfo(ctx.device(), CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof unified, &unified,
                        nullptr),
        "clGetDeviceInfo (CL_DEVICE_HOST_UNIFIED_MEMORY)");
  return unified ? ReadBackPath::mapped : ReadBackPath::staged;
}

const char* to_string(ReadBackPath path) {
  return path == ReadBackPath::staged ? "staged (pinned host memory)" : "mapped";
}

namespace {

std::size_t mask_bytes(const std::vector<MaskPiece>& pieces) {
  std::size_t end = 0;
  for (const MaskPiece& p : pieces) end = std::max(end, p.offset + p.count);
  return end;
}

}  // namespace

double ResultReader::read(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                          Precision precision, cl_mem positions, cl_mem normals, cl_mem mask,
                          const std::vector<MaskPiece>& pieces) {
  if (precision == Precision::f32)
    return path_ == ReadBackPath::staged
               ? read_staged<float>(out, samples, positions, normals, mask, pieces)
               : read_mapped<float>(out, samples, positions, normals, mask, pieces);
  return path_ == ReadBackPath::staged
             ? read_staged<double>(out, samples, positions, normals, mask, pieces)
             : read_mapped<double>(out, samples, positions, normals, mask, pieces);
}

template <typename T>
double ResultReader::read_staged(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                                 cl_mem positions, cl_mem normals, cl_mem mask,
                                 const std::vector<MaskPiece>& pieces) {
  const std::size_t points = total_samples(samples) * 3 * sizeof(T);
  const std::size_t masks = pieces.empty() ? 0 : mask_bytes(pieces);
  auto* base = static_cast<unsigned char*>(
      staging_.reserve((normals ? 2 : 1) * points + masks, "read-back staging"));
  unsigned char* normals_at = base + points;
  unsigned char* mask_at = base + (normals ? 2 : 1) * points;
  Batch batch;
  enqueue_read(batch, *ctx_, positions, 0, base, points, "read-back (positions)");
  if (normals) enqueue_read(batch, *ctx_, normals, 0, normals_at, points, "read-back (normals)");
  if (masks) enqueue_read(batch, *ctx_, mask, 0, mask_at, masks, "read-back (trim mask)");
  const double seconds = batch.wait("read-back");
  scatter_points<T>(out, samples, reinterpret_cast<const T*>(base),
                    normals ? reinterpret_cast<const T*>(normals_at) : nullptr);
  for (const MaskPiece& p : pieces)
    out.surfaces[p.surface].inside.assign(mask_at + p.offset, mask_at + p.offset + p.count);
  return seconds;
}

template <typename T>
double ResultReader::read_mapped(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                                 cl_mem positions, cl_mem normals, cl_mem mask,
                                 const std::vector<MaskPiece>& pieces) {
  const std::size_t points = total_samples(samples) * 3 * sizeof(T);
  const std::size_t masks = pieces.empty() ? 0 : mask_bytes(pieces);
  struct Mapping {
    cl_mem mem;
    std::size_t bytes;
    void* at = nullptr;
  };
  std::vector<Mapping> mappings;
  if (points > 0) {
    mappings.push_back({positions, points});
    if (normals) mappings.push_back({normals, points});
  }
  if (masks > 0) mappings.push_back({mask, masks});
  Batch maps;
  // Unmapped on every path, a map that failed part-way through included: the next evaluate()
  // writes these buffers (in-order queue: after the unmaps).
  Batch unmaps;
  const auto unmap = [&] {
    for (const Mapping& m : mappings)
      if (m.at)
        check(clEnqueueUnmapMemObject(ctx_->queue(), m.mem, m.at, 0, nullptr, unmaps.next()),
              "clEnqueueUnmapMemObject (read-back)");
    return unmaps.wait("read-back (unmap)");
  };
  double seconds = 0;
  try {
    for (Mapping& m : mappings) {
      cl_int status = CL_SUCCESS;
      m.at = clEnqueueMapBuffer(ctx_->queue(), m.mem, CL_FALSE, CL_MAP_READ, 0, m.bytes, 0, nullptr,
                                maps.next(), &status);
      if (status != CL_SUCCESS) m.at = nullptr;
      check(status, "clEnqueueMapBuffer (read-back)");
    }
    seconds = maps.wait("read-back (map)");
    const auto* p = static_cast<const T*>(points > 0 ? mappings[0].at : nullptr);
    const auto* n = static_cast<const T*>(points > 0 && normals ? mappings[1].at : nullptr);
    if (points > 0)
      scatter_points<T>(out, samples, p, n);
    else
      shape_results(out, samples, std::is_same_v<T, float> ? Precision::f32 : Precision::f64,
                    normals != nullptr);
    const auto* m = static_cast<const unsigned char*>(masks > 0 ? mappings.back().at : nullptr);
    for (const MaskPiece& piece : pieces)
      out.surfaces[piece.surface].inside.assign(m + piece.offset, m + piece.offset + piece.count);
  } catch (...) {
    try {
      unmap();
    } catch (const std::exception&) {
      // The first error is the one to report.
    }
    throw;
  }
  return seconds + unmap();
}

}  // namespace nurbs::opencl
