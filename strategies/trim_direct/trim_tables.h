// Direct trimming, the host half (Schollmeyer & Fröhlich 2009, §4): the trim loops as pieces
// monotone in u and v and the paper's two-level acceleration structure, packed into the two
// arrays the single-source classifier (strategies/trim_direct/trim_direct.h) reads; the C++
// compile of that classifier; the options and the cost counter every trimming strategy records.
//
// Where we deviate from the paper, and why:
//  * Pieces: the paper splits the trim curves (given as Bézier curves) at their u- and v-extrema;
//    we take the exact rational Bézier pieces of the NURBS trim curves (The NURBS Book A5.6, the
//    reference's trim_pieces) and split those at the roots of the derivative numerators
//    x'w - xw', isolated by the reference's Bernstein root isolation, so the host needs no
//    second root finder.
//  * Second level: the paper partitions each row again in u into cells with a precomputed
//    parity, each cell listing the curves that may cross it. We keep one list per row sorted by
//    u-min: pieces whose u-min is right of the sample count without reading them, pieces wholly
//    left are skipped, and only the overlapping ones are bisected -- the same bisections as the
//    paper's cells with one table fewer (a row walk is O(pieces in the row), where trim loops
//    of CAD faces hold a handful).
//  * Gaps: loops are closed only within Trim::tolerance; the straight segment between two ends
//    that differ is added as a degree-1 piece, as the reference closes its loops for counting.
//  * Precision: coordinates are stored relative to the centre of the trim's box (float keeps
//    relative precision; domains of CAD faces are often far from 0), and ε is a fraction of the
//    surface's domain diagonal, like --trim-band.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "reference/sampling.h"
#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::trim_direct {

// Options trim-epsilon=E (a fraction of the surface's domain diagonal, > 0 and < 1) and
// trim-iterations=N (1..64): the bisection's stopping rule.
struct Settings {
  double epsilon = 1e-9;
  int iterations = 40;
};
// Throws std::invalid_argument naming `strategy`, the option and the value when invalid.
Settings settings_from(const StrategyOptions& options, std::string_view strategy);

// A piece monotone in u and in v: Cartesian control points (u, v) and weights, in the trim's
// local frame (relative to TrimTables::SurfaceTrim's origin).
struct MonotonePiece {
  int degree = 0;
  std::vector<std::array<double, 3>> points;  // (u, v, w)
};

// The trim's loops as monotone pieces, in loop order, each loop exactly closed (a degree-1 piece
// bridges any gap between consecutive ends).
std::vector<MonotonePiece> monotone_pieces(const Trim& trim, double origin_u, double origin_v);

// One scene's tables, in T (float for the GPU stages, double where the device has it).
template <typename T>
struct TrimTables {
  struct SurfaceTrim {
    int base = -1;  // ints index of its tables; -1: untrimmed
    double origin_u = 0, origin_v = 0;
    T epsilon = 0;  // in (u, v) units
  };
  std::vector<T> reals;
  std::vector<std::int32_t> ints;
  std::vector<SurfaceTrim> surfaces;  // one per scene surface
  std::size_t pieces = 0, rows = 0, entries = 0;
};

template <typename T>
TrimTables<T> build_tables(const Scene& scene, const Settings& settings);

// The sample's coordinates in the trim's local frame, rounded once to T (what a device is given).
template <typename T>
T local_u(const typename TrimTables<T>::SurfaceTrim& s, double u) {
  return static_cast<T>(u - s.origin_u);
}
template <typename T>
T local_v(const typename TrimTables<T>::SurfaceTrim& s, double v) {
  return static_cast<T>(v - s.origin_v);
}

// The C++ compile of td_classify: 2 * (elements read) + (1 inside).
template <typename T>
int classify_packed(const TrimTables<T>& tables, std::size_t surface, T u, T v, int iterations);

// The cost counter: buffer elements read per classified sample.
struct Cost {
  std::uint64_t samples = 0, reads = 0;
  int max_reads = 0;
  void add(int packed) {
    const int r = packed / 2;
    ++samples;
    reads += static_cast<std::uint64_t>(r);
    max_reads = r > max_reads ? r : max_reads;
  }
};

// The C++ path over a surface's samples: the mask (1 inside) and the cost, for tests and the
// figures a device is compared with.
template <typename T>
std::vector<std::uint8_t> classify_samples(const TrimTables<T>& tables, std::size_t surface,
                                           const SurfaceSamples& samples, int iterations,
                                           Cost* cost = nullptr);

// DeviceInfo::details: trim_method, trim_epsilon, trim_iterations, and after a classification
// trim_reads_per_sample_mean / _max.
void record_settings(const Settings& settings, DeviceInfo& info);
void record_cost(const Cost& cost, DeviceInfo& info);

}  // namespace nurbs::trim_direct
