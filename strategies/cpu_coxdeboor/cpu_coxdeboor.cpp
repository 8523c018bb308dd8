#include "strategies/cpu_coxdeboor/cpu_coxdeboor.h"

#include <cstdint>
#include <optional>
#include <variant>

#include "reference/nurbs_math.h"
#include "reference/trim_classify.h"

namespace nurbs {
namespace {

Capabilities coxdeboor_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.trims = true;
  return c;
}

class CpuCoxDeBoor final : public Strategy {
 public:
  std::string_view name() const override { return "cpu-coxdeboor"; }
  Capabilities capabilities() const override { return coxdeboor_capabilities(); }
  DeviceInfo device() const override { return {"host CPU, 1 thread", "cpu", {}}; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32)
      nets_ = make_nets<float>(scene);
    else
      nets_ = make_nets<double>(scene);
    results_.resize(scene.surfaces.size());  // kept storage: see PointArray::reset
    trims_.clear();
    for (const Surface& s : scene.surfaces) trims_.push_back(s.trim);
    for (std::size_t i = 0; i < results_.size(); ++i) {
      results_[i].positions.reset(request.precision, samples_[i].count());
      results_[i].normals.reset(request.precision, request.normals ? samples_[i].count() : 0);
      results_[i].inside.clear();
    }
  }

  void evaluate() override {
    std::visit([this](const auto& nets) { evaluate_all(nets); }, nets_);
  }

  // The reference's classifier in double: the same crossings, so the harness's misclassification
  // metrics are exercised by a strategy whose answer is known to be right away from the boundary.
  bool classify() override {
    for (std::size_t i = 0; i < trims_.size(); ++i)
      if (trims_[i])
        results_[i].inside =
            classify_trim_samples(*trims_[i], samples_[i], /*with_distance=*/false, TrimScalar::f64,
                                  /*threads=*/1)  // single-threaded, like its evaluation
                .inside;
    return true;
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Into out's buffers: same-size copy-assignment and PointArray::reset keep their storage.
  void read_back_into(EvalResult& out) override {
    out.surfaces.resize(results_.size());
    for (std::size_t i = 0; i < results_.size(); ++i)
      copy_surface_into(out.surfaces[i], samples_[i], results_[i].positions, results_[i].normals,
                        &results_[i].inside);
  }

 private:
  struct Output {
    PointArray positions, normals;
    std::vector<std::uint8_t> inside;  // trimmed surfaces, after classify()
  };

  template <typename T>
  static std::vector<SurfaceNet<T>> make_nets(const Scene& scene) {
    std::vector<SurfaceNet<T>> nets;
    nets.reserve(scene.surfaces.size());
    for (const Surface& s : scene.surfaces) nets.emplace_back(s);
    return nets;
  }

  template <typename T>
  void evaluate_all(const std::vector<SurfaceNet<T>>& nets) {
    for (std::size_t i = 0; i < nets.size(); ++i) {
      const SurfaceSamples& samples = samples_[i];
      Output& out = results_[i];
      const std::size_t n = samples.count();
      for (std::size_t k = 0; k < n; ++k) {
        const T u = T(samples.u_of(k)), v = T(samples.v_of(k));
        out.positions.set(k, surface_point(nets[i], u, v));
        if (request_.normals) out.normals.set(k, surface_normal(nets[i], u, v));
      }
    }
  }

  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::variant<std::vector<SurfaceNet<float>>, std::vector<SurfaceNet<double>>> nets_;
  std::vector<Output> results_;
  std::vector<std::optional<Trim>> trims_;  // per surface, copied at prepare
};

}  // namespace

StrategyEntry cpu_coxdeboor_entry() {
  return host_entry<CpuCoxDeBoor>(
      {"cpu-coxdeboor", "Piegl & Tiller A2.1/A2.2/A4.3, the CPU baseline of 000 §5 and 002 §5",
       "strategy", coxdeboor_capabilities()});
}

}  // namespace nurbs
