#include "strategies/cpu_tensor/row_trim.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace nurbs::tensor {
namespace {

// About as many bins as pairs (each row then tests a handful of bounds), capped for loops of
// very many small pieces.
constexpr std::size_t kMaxBins = 4096;

TrimPieces<double> mirrored_pieces(const Trim& trim) {
  TrimPieces<double> pieces = trim_pieces<double>(trim);
  for (auto& loop : pieces.loops)
    for (TrimPiece<double>& piece : loop)
      for (auto& h : piece.h) std::swap(h[0], h[1]);
  return pieces;
}

}  // namespace

RowTrimClassifier::RowTrimClassifier(const Trim& trim) : mirrored_(mirrored_pieces(trim)) {
  lo_ = std::numeric_limits<double>::infinity();
  hi_ = -lo_;
  for (const auto& loop : mirrored_.loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const TrimPiece<double>& next = loop[(k + 1) % loop.size()];
      const Pair pair{&loop[k], &next, event_free_outside(loop[k], next)};
      pairs_.push_back(pair);
      lo_ = std::min(lo_, pair.bounds[0]);
      hi_ = std::max(hi_, pair.bounds[1]);
    }
  if (pairs_.empty()) return;
  const std::size_t bins = std::clamp<std::size_t>(pairs_.size(), 1, kMaxBins);
  bin_width_ =
      std::max((hi_ - lo_) / static_cast<double>(bins), std::numeric_limits<double>::min());
  bins_.resize(bins);
  for (std::uint32_t k = 0; k < pairs_.size(); ++k) {
    const auto [first, last] =
        std::pair(bin_index(pairs_[k].bounds[0]), bin_index(pairs_[k].bounds[1]));
    for (std::size_t b = first; b <= last; ++b) bins_[b].push_back(k);
  }
}

std::size_t RowTrimClassifier::bin_index(double u) const {
  const double at = std::floor((u - lo_) / bin_width_);
  if (!(at > 0)) return 0;  // also NaN
  return std::min(static_cast<std::size_t>(at), bins_.size() - 1);
}

void RowTrimClassifier::classify_row(double u, const double* v, std::size_t count,
                                     std::uint8_t* inside, Scratch& scratch) const {
  scratch.events.clear();
  if (!bins_.empty() && u >= lo_ && u <= hi_)
    for (std::uint32_t k : bins_[bin_index(u)]) {
      const Pair& pair = pairs_[k];
      if (u < pair.bounds[0] || u > pair.bounds[1]) continue;
      piece_crossing_events(*pair.piece, *pair.next, u, scratch.events, scratch.roots,
                            RootRefinement::newton);
    }
  std::sort(scratch.events.begin(), scratch.events.end());
  fill_row_from_events(scratch.events, v, count, inside);
}

void fill_row_from_events(const std::vector<double>& sorted_events, const double* along,
                          std::size_t count, std::uint8_t* inside) {
  // Samples before events[k] (and at or after events[k-1]) have the events from k on beyond them.
  std::size_t begin = 0;
  const std::size_t n = sorted_events.size();
  for (std::size_t k = 0; k <= n && begin < count; ++k) {
    const std::size_t end =
        k < n ? static_cast<std::size_t>(
                    std::lower_bound(along + begin, along + count, sorted_events[k]) - along)
              : count;
    std::memset(inside + begin, static_cast<int>((n - k) % 2), end - begin);
    begin = end;
  }
}

}  // namespace nurbs::tensor
