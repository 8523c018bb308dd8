// cpu-tensor's trimming: the reference's exact crossings (reference/trim_crossings.h) in double,
// computed once per output row rather than once per sample. An output row is one u sample with
// every v sample (contiguous in memory), so the loops are mirrored across u = v at prepare: the
// reference's "line v = const, events in u" becomes "line u = const, events in v" with the same
// code, and the even-odd rule does not care about the mirror. Each row visits only the pieces
// whose event-free bounds contain its u (a bin index over those bounds), sorts its few events and
// fills the row's mask in runs between them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "reference/trim.h"
#include "reference/trim_crossings.h"

namespace nurbs::tensor {

class RowTrimClassifier {
 public:
  // Per thread: reused between rows so a row allocates nothing.
  struct Scratch {
    std::vector<double> events, roots;
  };

  explicit RowTrimClassifier(const Trim& trim);
  // The index points into the pieces: moving keeps their storage, copying would not.
  RowTrimClassifier(const RowTrimClassifier&) = delete;
  RowTrimClassifier& operator=(const RowTrimClassifier&) = delete;
  RowTrimClassifier(RowTrimClassifier&&) = default;
  RowTrimClassifier& operator=(RowTrimClassifier&&) = default;

  // inside[b] for the samples (u, v[b]), b < count; v ascending (grid and span-grid lists are).
  void classify_row(double u, const double* v, std::size_t count, std::uint8_t* inside,
                    Scratch& scratch) const;

 private:
  struct Pair {  // a piece and the next one of its loop, for the junction between them
    const TrimPiece<double>* piece;
    const TrimPiece<double>* next;
    std::array<double, 2> bounds;  // event_free_outside, in u
  };
  std::size_t bin_index(double u) const;  // clamped to the bins

  TrimPieces<double> mirrored_;  // (w·v, w·u, w): "v" below is the surface's u
  std::vector<Pair> pairs_;
  std::vector<std::vector<std::uint32_t>> bins_;  // pairs whose bounds meet each u interval
  double lo_ = 0, hi_ = 0, bin_width_ = 1;
};

// Fills inside[0..count) from the sorted events of the row and its ascending sample coordinates:
// a sample is inside when an odd number of events lie strictly beyond it (inside_by_events), so
// the answer is constant between consecutive events and each run is one memset.
void fill_row_from_events(const std::vector<double>& sorted_events, const double* along,
                          std::size_t count, std::uint8_t* inside);

}  // namespace nurbs::tensor
