#include "strategies/sisl/sisl_strategy.h"

#include "reference/nurbs_math.h"

#if NURBSBENCH_HAVE_SISL
#include <fmt/format.h>

#include <memory>

extern "C" {
#include <sisl.h>
}
#endif

namespace nurbs {
namespace {

Capabilities sisl_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  return c;
}

#if NURBSBENCH_HAVE_SISL

struct SurfDeleter {
  void operator()(SISLSurf* s) const { freeSurf(s); }
};

// SISL's first parameter direction is our v and its second our u: SISL stores coefficients with
// the first index fastest and s1506 returns the grid first-direction fastest, which is then
// exactly our (i * count_v + j) / (a * NV + b) order, with no transposition.
std::unique_ptr<SISLSurf, SurfDeleter> make_sisl_surface(const Surface& s) {
  std::vector<double> knots_first(s.knots_v), knots_second(s.knots_u);
  std::vector<double> coefficients;
  coefficients.reserve(s.points.size() * 4);
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const double w = s.weights[k];
    coefficients.insert(coefficients.end(),
                        {s.points[k][0] * w, s.points[k][1] * w, s.points[k][2] * w, w});
  }
  // kind 2: rational B-spline, coefficients in homogeneous form; copy flag 1: SISL copies.
  SISLSurf* surf = newSurf(s.count_v, s.count_u, s.degree_v + 1, s.degree_u + 1, knots_first.data(),
                           knots_second.data(), coefficients.data(), 2, 3, 1);
  if (!surf) throw std::runtime_error("SISL newSurf failed");
  return std::unique_ptr<SISLSurf, SurfDeleter>(surf);
}

class SislStrategy final : public Strategy {
 public:
  std::string_view name() const override { return "sisl"; }
  Capabilities capabilities() const override { return sisl_capabilities(); }
  DeviceInfo device() const override {
    return {"host CPU, 1 thread", "cpu", {{"library", "SINTEF SISL (libsisl-dev)"}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    scene_ = &scene;
    samples_ = sample_parameters(scene, request.sampling);
    surfaces_.clear();
    nets_.clear();
    for (const Surface& s : scene.surfaces) {
      surfaces_.push_back(make_sisl_surface(s));
      nets_.emplace_back(s);
    }
    const int per_sample = request.normals ? 9 : 3;
    derivatives_.resize(samples_.size());
    normals_raw_.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      derivatives_[i].assign(samples_[i].count() * per_sample, 0.0);
      normals_raw_[i].assign(request.normals ? samples_[i].count() * 3 : 3, 0.0);
    }
  }

  void evaluate() override {
    const int ider = request_.normals ? 1 : 0;
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      SurfaceSamples& s = samples_[i];
      int status = 0;
      if (s.tensor) {
        s1506(surfaces_[i].get(), ider, static_cast<int>(s.v.size()), s.v.data(),
              static_cast<int>(s.u.size()), s.u.data(), derivatives_[i].data(),
              normals_raw_[i].data(), &status);
        if (status < 0) throw std::runtime_error(fmt::format("SISL s1506 failed: {}", status));
      } else {
        const int per_sample = request_.normals ? 9 : 3;
        double der[12];
        for (std::size_t k = 0; k < s.count(); ++k) {
          double par[2] = {s.v[k], s.u[k]};
          int left1 = 0, left2 = 0;
          s1424(surfaces_[i].get(), ider, ider, par, &left1, &left2, der, &status);
          if (status < 0) throw std::runtime_error(fmt::format("SISL s1424 failed: {}", status));
          // s1424 order: (0,0), (1,0), (0,1), ... with the first direction fastest.
          const int copy = per_sample == 9 ? 9 : 3;
          std::copy(der, der + copy, derivatives_[i].begin() + k * per_sample);
        }
      }
    }
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Into out's buffers: same-size copy-assignment and PointArray::reset keep their storage.
  void read_back_into(EvalResult& out) override {
    out.surfaces.resize(samples_.size());
    const int per_sample = request_.normals ? 9 : 3;
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      SurfaceResult& r = out.surfaces[i];
      r.samples = samples_[i];
      const std::size_t n = samples_[i].count();
      // SISL computes in double; an f32 request gets those results rounded to float.
      r.positions.reset(request_.precision, n);
      r.normals.reset(request_.precision, request_.normals ? n : 0);
      const double* d = derivatives_[i].data();
      for (std::size_t k = 0; k < n; ++k) {
        const double* p = d + k * per_sample;
        r.positions.set(k, Vec3<double>{p[0], p[1], p[2]});
        if (!request_.normals) continue;
        // SISL's first direction is our v: Su = p[6..8], Sv = p[3..5].
        const Vec3<double> su{p[6], p[7], p[8]}, sv{p[3], p[4], p[5]};
        Vec3<double> n3;
        if (!detail::normalize_if_resolved(cross(su, sv), su, sv, n3))
          n3 = surface_normal(nets_[i], samples_[i].u_of(k), samples_[i].v_of(k));
        r.normals.set(k, n3);
      }
    }
  }

 private:
  EvalRequest request_;
  const Scene* scene_ = nullptr;
  std::vector<SurfaceSamples> samples_;
  std::vector<std::unique_ptr<SISLSurf, SurfDeleter>> surfaces_;
  std::vector<SurfaceNet<double>> nets_;
  std::vector<std::vector<double>> derivatives_, normals_raw_;
};

#endif

}  // namespace

StrategyEntry sisl_entry() {
  return {"sisl",
          "SINTEF SISL s1506 grid evaluation (s1424 per sample for explicit lists)",
          "peer",
          [] {
#if NURBSBENCH_HAVE_SISL
            return Availability{true, ""};
#else
            return Availability{false, "not built with SISL (install libsisl-dev)"};
#endif
          },
          sisl_capabilities,
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
#if NURBSBENCH_HAVE_SISL
            return std::make_unique<SislStrategy>();
#else
            throw std::runtime_error("not built with SISL (install libsisl-dev)");
#endif
          }};
}

}  // namespace nurbs
