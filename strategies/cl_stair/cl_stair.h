// cl-stair: RPNS (003 §3.2) stair basis as an OpenCL kernel. Each KSQuad (a non-empty span pair
// with samples) is cut into tiles of at most a few hundred samples, one work-group each (enough
// groups to fill a GPU: one group per KSQuad gave patch144 81 groups on 132 SMs); a group caches
// its KSQuad's (p+1)(q+1) homogeneous control points and the per-span constant denominators in
// local memory, and its work-items evaluate the tile's samples. The host bins grid parameters by
// span once in prepare(); span-grid samples are binned natively (span s's T+1 samples belong to
// KSQuad s, its end knot included). Explicit lists are refused (not separable). float32 by
// default, float64 where the device has cl_khr_fp64. Degree <= 15 (the validation limit); the
// control-point cache in local memory is sized for the scene's largest degrees and refused, naming
// CL_DEVICE_LOCAL_MEM_SIZE, where the device has less. The programs are built once per precision
// (first prepare()), and update_control_points() re-sends only the control points (003 §5);
// DeviceInfo::details "program_builds" counts the builds, "local_mem_bytes" is the kernel's local
// memory, "ksquads", "work_groups" and "tile_samples" the launch's shape, "bytes_uploaded"
// (prepare()) and "bytes_updated" (update_control_points()) what was sent, "read_back" the
// read-back's path (strategies/opencl/cl_read_back.h). Every phase's transfers are one write per
// buffer and one completion wait; read_back_into() reuses the result's storage.
//
// Trims (Capabilities::trims): classify() runs direct trimming (Schollmeyer & Fröhlich 2009) on
// the device, classify.cl with the single-source strategies/trim_direct/trim_direct.h, one
// work-item per grid sample, in the request's precision; the cost counter (buffer elements read
// per sample, mean and max) goes to DeviceInfo::details when device() is next asked (read from
// the device there, not in the timed read-back).
//
// Options (StrategyOptions.extra): "device" = N, the N-th OpenCL device over all platforms;
// "read-back" = staged | mapped (strategies/opencl/cl_read_back.h; default by the device);
// "trim-epsilon" = E (bisection width, a fraction of the domain diagonal; default 1e-9) and
// "trim-iterations" = N (1..64, default 40).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor cl_stair_descriptor();
StrategyEntry cl_stair_entry();

}  // namespace nurbs

#include <vector>

#include "reference/scalar.h"

namespace nurbs {

// Tests: the OpenCL build of the stair basis (stair.cl, kernel stair_basis_test) at parameters
// `u` of span `span`, on OpenCL device 0: (degree + 1) values per parameter, the basis or (with
// `derivative`) its derivative. OpenCL builds only.
std::vector<double> stair_basis_on_device(int span, int degree, const std::vector<double>& knots,
                                          const std::vector<double>& u, Precision precision,
                                          bool derivative = false);

}  // namespace nurbs
