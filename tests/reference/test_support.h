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

inline double distance(const Point3& a, const Point3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

}  // namespace nurbs::test
