#include "strategies/occt/occt_strategy.h"

#include "reference/nurbs_math.h"

#if NURBSBENCH_HAVE_OCCT
#include <fmt/format.h>

#include <GeomAdaptor_Surface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#endif

namespace nurbs {
namespace {

Capabilities occt_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;  // Geom_BSplineSurface allows up to 25
  return c;
}

#if NURBSBENCH_HAVE_OCCT

// OCCT wants distinct knots with multiplicities.
void distinct_knots(const std::vector<double>& knots, TColStd_Array1OfReal*& values,
                    TColStd_Array1OfInteger*& mults) {
  std::vector<double> v;
  std::vector<int> m;
  for (double k : knots) {
    if (!v.empty() && v.back() == k)
      ++m.back();
    else {
      v.push_back(k);
      m.push_back(1);
    }
  }
  values = new TColStd_Array1OfReal(1, static_cast<int>(v.size()));
  mults = new TColStd_Array1OfInteger(1, static_cast<int>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    values->SetValue(static_cast<int>(i) + 1, v[i]);
    mults->SetValue(static_cast<int>(i) + 1, m[i]);
  }
}

Handle(Geom_BSplineSurface) make_occt_surface(const Surface& s) {
  TColgp_Array2OfPnt poles(1, s.count_u, 1, s.count_v);
  TColStd_Array2OfReal weights(1, s.count_u, 1, s.count_v);
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      const Point3& p = s.point(i, j);
      poles.SetValue(i + 1, j + 1, gp_Pnt(p[0], p[1], p[2]));
      weights.SetValue(i + 1, j + 1, s.weight(i, j));
    }
  TColStd_Array1OfReal *uk = nullptr, *vk = nullptr;
  TColStd_Array1OfInteger *um = nullptr, *vm = nullptr;
  distinct_knots(s.knots_u, uk, um);
  distinct_knots(s.knots_v, vk, vm);
  std::unique_ptr<TColStd_Array1OfReal> uk_owner(uk), vk_owner(vk);
  std::unique_ptr<TColStd_Array1OfInteger> um_owner(um), vm_owner(vm);
  try {
    return new Geom_BSplineSurface(poles, weights, *uk, *vk, *um, *vm, s.degree_u, s.degree_v);
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(
        fmt::format("OCCT rejected surface '{}': {}", s.name, e.GetMessageString()));
  }
}

// Two ways a user of OCCT evaluates a surface: Geom_BSplineSurface::D0/D1 directly (`occt`), or
// through GeomAdaptor_Surface (`occt-cached`), which keeps a BSplSLib_Cache — the current span's
// polynomial coefficients — and rebuilds it only when a sample leaves that span, so a grid walked
// row by row pays the span set-up once per span run instead of once per sample.
class OcctStrategy final : public Strategy {
 public:
  explicit OcctStrategy(bool cached) : cached_(cached) {}
  std::string_view name() const override { return cached_ ? "occt-cached" : "occt"; }
  Capabilities capabilities() const override { return occt_capabilities(); }
  DeviceInfo device() const override {
    return {"host CPU, 1 thread",
            "cpu",
            {{"library", "OpenCASCADE " OCC_VERSION_COMPLETE},
             {"path", cached_ ? "GeomAdaptor_Surface (BSplSLib_Cache)" : "Geom_BSplineSurface"}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    surfaces_.clear();
    adaptors_.clear();
    nets_.clear();
    for (const Surface& s : scene.surfaces) {
      surfaces_.push_back(make_occt_surface(s));
      if (cached_) adaptors_.emplace_back(surfaces_.back());
      nets_.emplace_back(s);
    }
    points_.resize(samples_.size());
    derivatives_.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      points_[i].resize(samples_[i].count());
      derivatives_[i].resize(request.normals ? samples_[i].count() * 2 : 0);
    }
  }

  void evaluate() override {
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      // Both classes have the same D0/D1 signatures.
      auto evaluate_samples = [&](const auto& surface) {
        const SurfaceSamples& s = samples_[i];
        const std::size_t n = s.count();
        if (request_.normals)
          for (std::size_t k = 0; k < n; ++k)
            surface.D1(s.u_of(k), s.v_of(k), points_[i][k], derivatives_[i][2 * k],
                       derivatives_[i][2 * k + 1]);
        else
          for (std::size_t k = 0; k < n; ++k) surface.D0(s.u_of(k), s.v_of(k), points_[i][k]);
      };
      if (cached_)
        evaluate_samples(adaptors_[i]);
      else
        evaluate_samples(*surfaces_[i]);
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
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      SurfaceResult& r = out.surfaces[i];
      r.samples = samples_[i];
      const std::size_t n = samples_[i].count();
      r.positions.reset(request_.precision, n);
      r.normals.reset(request_.precision, request_.normals ? n : 0);
      for (std::size_t k = 0; k < n; ++k) {
        const gp_Pnt& p = points_[i][k];
        r.positions.set(k, Vec3<double>{p.X(), p.Y(), p.Z()});
        if (!request_.normals) continue;
        const gp_Vec &du = derivatives_[i][2 * k], &dv = derivatives_[i][2 * k + 1];
        const Vec3<double> su{du.X(), du.Y(), du.Z()}, sv{dv.X(), dv.Y(), dv.Z()};
        Vec3<double> n3;
        if (!detail::normalize_if_resolved(cross(su, sv), su, sv, n3))
          n3 = surface_normal(nets_[i], samples_[i].u_of(k), samples_[i].v_of(k));
        r.normals.set(k, n3);
      }
    }
  }

 private:
  bool cached_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<Handle(Geom_BSplineSurface)> surfaces_;
  std::vector<GeomAdaptor_Surface> adaptors_;
  std::vector<SurfaceNet<double>> nets_;
  std::vector<std::vector<gp_Pnt>> points_;
  std::vector<std::vector<gp_Vec>> derivatives_;
};

#endif

StrategyEntry occt_entry(bool cached) {
  return {cached ? "occt-cached" : "occt",
          cached ? "OpenCASCADE GeomAdaptor_Surface D0/D1 per sample, span cache reused"
                 : "OpenCASCADE Geom_BSplineSurface D0/D1 per sample",
          "peer",
          [] {
#if NURBSBENCH_HAVE_OCCT
            return Availability{true, ""};
#else
            return Availability{false,
                                "not built with OpenCASCADE (install libocct-modeling-data-dev)"};
#endif
          },
          occt_capabilities,
          [cached](const StrategyOptions&) -> std::unique_ptr<Strategy> {
#if NURBSBENCH_HAVE_OCCT
            return std::make_unique<OcctStrategy>(cached);
#else
            (void)cached;
            throw std::runtime_error("not built with OpenCASCADE");
#endif
          }};
}

}  // namespace

StrategyEntry occt_entry() {
  return occt_entry(false);
}
StrategyEntry occt_cached_entry() {
  return occt_entry(true);
}

}  // namespace nurbs
