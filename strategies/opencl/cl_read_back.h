// The results of an OpenCL strategy into the harness's EvalResult (Strategy::read_back_into),
// reusing its storage, in one of two ways:
//
//   staged: one clEnqueueReadBuffer per device buffer, one completion wait, into pinned host
//     memory (PinnedHost, allocated once per strategy and grown), then one copy from there into
//     `out` (strategies/host_results.h scatter_points). The path for a discrete GPU: a read into
//     pageable memory (a std::vector) goes through the driver's bounce buffers at a fraction of
//     what the link moves from page-locked memory, and one transfer per surface into `out`'s
//     vectors would pay a command per surface on top; the host copy after the DMA runs at memcpy
//     speed.
//   mapped: clEnqueueMapBuffer (CL_MAP_READ) of the device buffers, one copy from the mapping
//     into `out`, unmap. Where device memory is host memory (PoCL on the CPU, an integrated GPU:
//     CL_DEVICE_HOST_UNIFIED_MEMORY) the map is the buffer itself, so the copy into `out` is the
//     only pass over the bytes; staging would add a second. Measured on PoCL (2-core EPYC, patch144
//     at 2048², 50 MB): mapped 15.6 GB/s, staged 8.9 GB/s, and one clEnqueueReadBuffer per surface
//     straight into `out` 7-9 GB/s on one surface but 3.7 GB/s on 4096 (a command each).
//
// The default follows CL_DEVICE_HOST_UNIFIED_MEMORY; StrategyOptions.extra["read-back"] =
// "staged" | "mapped" overrides it, so both can be measured on a GPU.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "reference/sampling.h"
#include "strategies/opencl/cl_device.h"
#include "strategies/opencl/cl_pinned.h"
#include "strategies/strategy.h"

namespace nurbs::opencl {

enum class ReadBackPath { staged, mapped };

// The "read-back" option, else mapped on a host-unified-memory device and staged otherwise.
// Throws std::runtime_error on another value.
ReadBackPath read_back_path(const Context& ctx, const StrategyOptions& options);
const char* to_string(ReadBackPath path);

// A trimmed surface's mask: `count` bytes at `offset` of the mask buffer go to
// out.surfaces[surface].inside.
struct MaskPiece {
  std::size_t surface = 0, offset = 0, count = 0;
};

class ResultReader {
 public:
  ResultReader(const Context& ctx, ReadBackPath path) : ctx_(&ctx), path_(path), staging_(ctx) {}

  ReadBackPath path() const { return path_; }

  // Every surface's points, back to back in `samples` order as the kernels write them (x y z per
  // point, `precision`'s scalar), from `positions` (and `normals` unless null) into `out`, and the
  // trim masks of `pieces` from `mask` (ignored when `pieces` is empty). Returns the device
  // seconds of its commands, summed: the transfers (staged), or the maps and unmaps (mapped: on a
  // unified-memory device the bytes move in the host copy, on the wall clock only).
  double read(EvalResult& out, const std::vector<SurfaceSamples>& samples, Precision precision,
              cl_mem positions, cl_mem normals, cl_mem mask, const std::vector<MaskPiece>& pieces);

 private:
  template <typename T>
  double read_staged(EvalResult& out, const std::vector<SurfaceSamples>& samples, cl_mem positions,
                     cl_mem normals, cl_mem mask, const std::vector<MaskPiece>& pieces);
  template <typename T>
  double read_mapped(EvalResult& out, const std::vector<SurfaceSamples>& samples, cl_mem positions,
                     cl_mem normals, cl_mem mask, const std::vector<MaskPiece>& pieces);

  const Context* ctx_;
  ReadBackPath path_;
  PinnedHost staging_;
};

}  // namespace nurbs::opencl
