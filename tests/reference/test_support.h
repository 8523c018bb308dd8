// Small helpers shared by the tests: samplings, reading tests/data, and recording the worst error
// a test measured (printed and stored as a GoogleTest property, so a CI log shows the margin).
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "reference/sampling.h"
#include "reference/surface.h"

namespace nurbs::test {

// The samplings tests ask for: an NU x NV grid, T steps per non-empty span.
inline Sampling grid(int nu, int nv) {
  Sampling s;
  s.grid_u = nu;
  s.grid_v = nv;
  return s;
}
inline Sampling span_grid(int steps) {
  Sampling s;
  s.mode = SamplingMode::span_grid;
  s.span_steps = steps;
  return s;
}

inline nlohmann::json load_test_data(const std::string& file) {
  const std::string path = std::string(NURBSBENCH_TEST_DATA) + "/" + file;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return nlohmann::json::parse(in);
}

// The largest value of some error measure over a test, with where it happened.
class Worst {
 public:
  explicit Worst(std::string what) : what_(std::move(what)) {}
  ~Worst() {
    const std::string line = fmt::format("{:.3e}{}", value_, where_.empty() ? "" : " at " + where_);
    std::cout << "[ measured ] " << what_ << ": " << line << "\n";
    ::testing::Test::RecordProperty(what_, line);
  }
  Worst(const Worst&) = delete;
  Worst& operator=(const Worst&) = delete;

  // `where` is called only when the value is a new maximum (formatting is not free).
  template <typename Where>
  void update(double value, Where&& where) {
    if (std::isnan(value) || value > value_) {
      value_ = std::isnan(value) ? INFINITY : value;
      where_ = where();
    }
  }
  double value() const { return value_; }

 private:
  std::string what_;
  double value_ = 0;
  std::string where_;
};

// Clamped knots on [0, 1] for `count` control points of `degree`, interior knots non-uniform and
// one of them repeated `degree` times (a crease: empty spans and 0/0 terms inside the recursion).
inline std::vector<double> knots_with_crease(int degree, int count) {
  std::vector<double> k(static_cast<std::size_t>(degree + 1), 0.0);
  const int interior = count - degree - 1;
  for (int i = 1; i <= interior; ++i) {
    const double t = static_cast<double>(i) / (interior + 1);
    k.push_back(t * t * (3 - 2 * t));
  }
  // repeat the middle interior knot up to `degree` times in total
  if (interior >= degree) {
    const std::size_t mid = static_cast<std::size_t>(degree + interior / 2);
    for (int r = 1; r < degree && mid + static_cast<std::size_t>(r) < k.size(); ++r)
      k[mid + static_cast<std::size_t>(r)] = k[mid];
  }
  k.resize(static_cast<std::size_t>(count + 1), 1.0);
  k.insert(k.end(), static_cast<std::size_t>(degree), 1.0);
  return k;
}

inline double distance(const Point3& a, const Point3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

}  // namespace nurbs::test
