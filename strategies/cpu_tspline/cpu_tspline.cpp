#include "strategies/cpu_tspline/cpu_tspline.h"

#include <memory>

#include "reference/tspline.h"
#include "reference/validation.h"

namespace nurbs {
namespace {

Capabilities tspline_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.tspline = true;
  c.tspline_only = true;
  // Only the points move (deforming frames): the influence index is kept.
  c.updates_control_points = true;
  return c;
}

class CpuTSpline final : public Strategy {
 public:
  std::string_view name() const override { return "cpu-tspline"; }
  Capabilities capabilities() const override { return tspline_capabilities(); }
  DeviceInfo device() const override { return {"host CPU, 1 thread", "cpu", {}}; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    surfaces_.clear();
    for (const Surface& s : scene.surfaces)
      surfaces_.push_back({s.tspline, std::make_shared<TSplineInfluence>(*s.tspline, s.name)});
    results_.resize(scene.surfaces.size());  // kept storage: see PointArray::reset
    for (std::size_t i = 0; i < results_.size(); ++i) {
      results_[i].positions.reset(request.precision, samples_[i].count());
      results_[i].normals.reset(request.precision, request.normals ? samples_[i].count() : 0);
    }
  }

  // The index depends on the local knot vectors and the domain only; a frame that changes them is
  // a new topology and is prepared again.
  void update_control_points(const Scene& scene) override {
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const TSplineSurface& now = *scene.surfaces[i].tspline;
      const TSplineSurface& was = *surfaces_[i].tspline;
      if (now.knots_u != was.knots_u || now.knots_v != was.knots_v || now.u_min != was.u_min ||
          now.u_max != was.u_max || now.v_min != was.v_min || now.v_max != was.v_max) {
        prepare(scene, request_);
        return;
      }
      surfaces_[i].tspline = scene.surfaces[i].tspline;
    }
  }

  void evaluate() override {
    if (request_.precision == Precision::f32)
      evaluate_all<float>();
    else
      evaluate_all<double>();
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
      copy_surface_into(out.surfaces[i], samples_[i], results_[i].positions, results_[i].normals);
  }

 private:
  struct Prepared {
    std::shared_ptr<const TSplineSurface> tspline;
    std::shared_ptr<const TSplineInfluence> index;
  };
  struct Output {
    PointArray positions, normals;
  };

  template <typename T>
  void evaluate_all() {
    const int order = request_.normals ? 1 : 0;
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const SurfaceSamples& samples = samples_[i];
      const Prepared& s = surfaces_[i];
      Output& out = results_[i];
      for (std::size_t k = 0; k < samples.count(); ++k) {
        const TSplineEvaluation<T> e =
            evaluate_tspline<T>(*s.tspline, *s.index, samples.u_of(k), samples.v_of(k), order);
        out.positions.set(k, e.point);
        if (order) out.normals.set(k, e.normal);
      }
    }
  }

  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<Prepared> surfaces_;
  std::vector<Output> results_;
};

}  // namespace

StrategyEntry cpu_tspline_entry() {
  return host_entry<CpuTSpline>(
      {"cpu-tspline",
       "001 (Krishnamurthy & Yasui) eq. 4 and Fig 7: point-based T-spline, region pre-processing "
       "+ direct blending functions, on the CPU",
       "strategy", tspline_capabilities()});
}

}  // namespace nurbs
