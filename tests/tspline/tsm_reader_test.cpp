// The Rhino #TS0200 reader (scenes/tsm) on the six sample models (data/tsplines of the shared data
// folder), with checks that do not trust the reader: simple.tsm's corners and boundary curves
// against what the file's own records say (force-bezier-end-conditions 1 = clamped ends), partition
// of unity on the analysis-suitable mesh, and malformed variants of simple.tsm refused with file,
// line, field and value.
#include "scenes/tsm/tsm_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "reference/nurbs_math.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

using LD = long double;

// Copies of the shared data folder's data/tsplines (scenes/data/tsplines/README.md).
const std::string kData = std::string(NURBSBENCH_SOURCE_DIR) + "/scenes/data/tsplines/";

std::string file_text(const std::string& name) {
  std::ifstream in(kData + name, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

// The control points as the file lists them (`0g x y z w`), read here without the reader.
std::vector<Point3> raw_points(const std::string& text) {
  std::vector<Point3> points;
  for (const std::string& line : lines_of(text)) {
    std::stringstream s(line);
    std::string type;
    Point3 p;
    if (s >> type && type == "0g" && s >> p[0] >> p[1] >> p[2]) points.push_back(p);
  }
  return points;
}

struct Imported {
  TMesh mesh;
  TSplineSurface surface;
};
Imported import(const std::string& name) {
  Imported out{load_tsm_file(kData + name), {}};
  out.surface = infer_tspline(out.mesh, name);
  return out;
}

LD distance(const Vec3<LD>& a, const Point3& b) {
  return std::hypot(a[0] - LD(b[0]), a[1] - LD(b[1]), a[2] - LD(b[2]));
}

TEST(TsmReader, SimpleHasItsTJunctionAndIsAnalysisSuitable) {
  const Imported simple = import("simple.tsm");
  // 23 points on a 5x5 index grid (Bézier ends add a repeated line inside each side): the two
  // missing are the T-junction's column above it.
  EXPECT_EQ(simple.surface.count(), 23u);
  EXPECT_EQ(simple.mesh.knots_s, (std::vector<double>{0, 0, 0.5, 1, 1}));
  EXPECT_EQ(simple.mesh.knots_t, (std::vector<double>{0, 0, 0.5, 1, 1}));
  EXPECT_EQ(analysis_suitability_violation(simple.mesh), "");
}

// force-bezier-end-conditions 1: at a domain corner only the corner point's blending function is
// non-zero, so the corner is interpolated. The corner points are the file's 0g points at the
// corners of the control net's xy bounding box (the net is planar in xy).
TEST(TsmReader, SimpleInterpolatesItsCornerPoints) {
  const Imported simple = import("simple.tsm");
  const TSplineSurface& s = simple.surface;
  const TSplineInfluence index(s, "simple");
  const std::vector<Point3> raw = raw_points(file_text("simple.tsm"));
  ASSERT_EQ(raw.size(), 23u);
  for (const double u : {s.u_min, s.u_max})
    for (const double v : {s.v_min, s.v_max}) {
      const TSplineEvaluation<LD> e = evaluate_tspline(s, index, u, v);
      const double x = u == s.u_min ? 0 : 30, y = v == s.v_min ? 0 : 30;
      const auto corner = std::find_if(raw.begin(), raw.end(), [&](const Point3& p) {
        return std::fabs(p[0] - x) < 1e-9 && std::fabs(p[1] - y) < 1e-9;
      });
      ASSERT_NE(corner, raw.end());
      EXPECT_LE(distance(e.point, *corner), 4 * scalar_epsilon<LD>() * 30) << u << ", " << v;
    }
}

// On a boundary of a clamped T-spline only that boundary's points contribute: the edge is the
// cubic B-spline curve of those points on the boundary's knot vector. From the file: the bottom
// and left sides are two edges of interval 0.5 (e records), the top side one edge of interval 1
// (the T-junction's column stops below it), so the knots are clamped [0, 0.5, 1] and [0, 1].
TEST(TsmReader, SimpleBoundaryCurvesAreTheirNurbsCurves) {
  const Imported simple = import("simple.tsm");
  const TSplineSurface& s = simple.surface;
  const TSplineInfluence index(s, "simple");
  const std::vector<Point3> raw = raw_points(file_text("simple.tsm"));
  struct Side {
    bool along_u;    // the side runs along u (fixed v) or along v (fixed u)
    double fixed;    // its fixed parameter
    int coordinate;  // which of x, y is fixed on it (0 or 1), and its value
    double value;
    std::vector<double> knots;
  };
  const std::vector<double> two_spans{0, 0, 0, 0, 0.5, 1, 1, 1, 1},
      one_span{0, 0, 0, 0, 1, 1, 1, 1};
  for (const Side& side :
       {Side{true, s.v_min, 1, 0, two_spans}, Side{true, s.v_max, 1, 30, one_span},
        Side{false, s.u_min, 0, 0, two_spans}}) {
    std::vector<Point3> row;
    for (const Point3& p : raw)
      if (std::fabs(p[side.coordinate] - side.value) < 1e-9) row.push_back(p);
    std::sort(row.begin(), row.end(), [&](const Point3& a, const Point3& b) {
      return a[1 - side.coordinate] < b[1 - side.coordinate];
    });
    Surface curve;  // the curve, as a NURBS surface linear in v with both rows equal
    curve.degree_u = 3;
    curve.degree_v = 1;
    curve.count_u = static_cast<int>(row.size());
    curve.count_v = 2;
    curve.knots_u = side.knots;
    curve.knots_v = {0, 0, 1, 1};
    for (const Point3& p : row) {
      curve.points.insert(curve.points.end(), {p, p});
      curve.weights.insert(curve.weights.end(), {1.0, 1.0});
    }
    validate_surface(curve, 0, "test");
    const SurfaceNet<LD> net(curve);
    for (int a = 0; a <= 64; ++a) {
      const double t = a / 64.0;
      const double u = side.along_u ? t : side.fixed, v = side.along_u ? side.fixed : t;
      const Vec3<LD> expected = surface_point(net, LD(t), LD(0));
      const TSplineEvaluation<LD> e = evaluate_tspline(s, index, u, v, 0);
      Point3 expected_point{double(expected[0]), double(expected[1]), double(expected[2])};
      EXPECT_LE(distance(e.point, expected_point), 1e-13L) << u << ", " << v;
    }
  }
}

TEST(TsmReader, BlendingFunctionsOfTheImportedModels) {
  test::Worst worst("max |sum of blending functions - 1| (simple, fan)");
  for (const char* name : {"simple.tsm", "fan.tsm"}) {
    const Imported m = import(name);
    for (int a = 0; a <= 32; ++a)
      for (int b = 0; b <= 32; ++b) {
        const double u = m.surface.u_min + (m.surface.u_max - m.surface.u_min) * a / 32;
        const double v = m.surface.v_min + (m.surface.v_max - m.surface.v_min) * b / 32;
        const LD error = std::fabs(tspline_blending_sum(m.surface, u, v) - 1);
        worst.update(double(error), [&] { return fmt::format("{} ({}, {})", name, u, v); });
        ASSERT_LE(error, 64 * scalar_epsilon<LD>()) << name << " (" << u << ", " << v << ")";
      }
  }
  // gearbox2-9.tsm imports but is not analysis-suitable: its blending functions need not (and do
  // not) sum to one, and its surface is defined by the rational form alone.
  const Imported gearbox = import("gearbox2-9.tsm");
  EXPECT_NE(analysis_suitability_violation(gearbox.mesh), "");
}

// mouse, Bike: concave boundary corners (non-rectangular domains); face: holes. The reason names
// a vertex record's line.
TEST(TsmReader, NonRectangularModelsAreRefusedNamingTheVertex) {
  for (const char* name : {"mouse.tsm", "Bike.tsm", "face.tsm"}) {
    try {
      load_tsm_file(kData + name);
      ADD_FAILURE() << name << " imported";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("only rectangular domains are supported"), std::string::npos) << what;
      const std::string prefix = kData + name + ":";
      ASSERT_EQ(what.rfind(prefix, 0), 0u) << what;
      const int line = std::stoi(what.substr(prefix.size()));
      const std::vector<std::string> lines = lines_of(file_text(name));
      ASSERT_GE(line, 1);
      EXPECT_EQ(lines[line - 1].rfind("v ", 0), 0u) << what << " -> " << lines[line - 1];
    }
  }
}

// simple.tsm with one line replaced (or the text cut): the error names the file, the line, the
// field and the value.
struct Malformed {
  const char* name;
  const char* find;     // a whole line of simple.tsm, or a prefix to cut the file after
  const char* replace;  // nullptr: cut the file after `find`
  std::vector<const char*> expected;  // parts of the message
  bool names_line = true;
};

TEST(TsmReader, MalformedFilesAreRefusedWithTheReason) {
  const std::string simple = file_text("simple.tsm");
  const std::vector<Malformed> cases = {
      {"truncated record", "l 11 14 1", nullptr, {"truncated record"}},
      {"bad number", "0g 5 0 0 1", "0g 5 zero 0 1", {"0g y = zero", "not a finite number"}},
      {"nan", "0g 5 0 0 1", "0g nan 0 0 1", {"0g x = nan", "not a finite number"}},
      {"zero weight", "0g 5 0 0 1", "0g 5 0 0 0", {"0g w = 0", "weights must be > 0"}},
      {"dangling half-edge",
       "l 11 14 1 0 0 0 0",
       "l 11 99 1 0 0 0 0",
       {"l half-edge = 99", "no such half-edge"}},
      {"dangling vertex",
       "l 11 14 1 0 0 0 0",
       "l 11 14 1 42 0 0 0",
       {"l vertex = 42", "no such vertex"}},
      {"bad integer",
       "l 11 14 1 0 0 0 0",
       "l 11 1.5 1 0 0 0 0",
       {"l next = 1.5", "not an integer"}},
      // Named at the vertex's own record (checked below), not at the edited half-edge.
      {"star point",
       "l 4 18 7 4 2 3 1",
       "l 4 18 7 4 2 3 0",
       {"vertex 4", "270 degrees", "extraordinary (star) point"},
       false},
      // Named at the half-edge where the walk around a face fails to close, not at the e record.
      {"intervals do not close", "e 9 1", "e 9 2", {"do not close up"}, false},
      {"bad direction", "v 0 EAST", "v 0 UP", {"v direction = UP"}},
      {"not a tsm file", "#TS0200", "#TS0100", {":1: header = #TS0100", "#TS0200"}},
  };
  const std::vector<std::string> lines = lines_of(simple);
  for (const Malformed& c : cases) {
    std::string text;
    int line = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const bool hit =
          line == 0 && (c.replace ? lines[i] == c.find : lines[i].rfind(c.find, 0) == 0);
      if (hit) line = static_cast<int>(i) + 1;
      if (hit && !c.replace) {
        text += c.find;
        break;
      }
      text += (hit ? std::string(c.replace) : lines[i]) + "\n";
    }
    ASSERT_GT(line, 0) << c.name;
    try {
      parse_tsm(text, "bad.tsm");
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      if (c.names_line) {
        EXPECT_NE(what.find(fmt::format("bad.tsm:{}:", line)), std::string::npos)
            << c.name << ": " << what;
      }
      if (std::string(c.name) == "star point") {
        int v_records = 0, vertex_line = 0;
        for (std::size_t i = 0; i < lines.size() && !vertex_line; ++i)
          if (lines[i].rfind("v ", 0) == 0 && v_records++ == 4)
            vertex_line = static_cast<int>(i) + 1;
        EXPECT_NE(what.find(fmt::format("bad.tsm:{}: vertex 4", vertex_line)), std::string::npos)
            << what;
      }
      for (const char* part : c.expected)
        EXPECT_NE(what.find(part), std::string::npos) << c.name << ": " << what;
    }
  }
  EXPECT_THROW(load_tsm_file(kData + "no-such-file.tsm"), InputError);
  EXPECT_THROW(parse_tsm("", "empty.tsm"), InputError);
}

// Every truncation of simple.tsm, and every single-byte corruption of a stretch of it, is read or
// refused with an InputError: never another exception, never a crash.
TEST(TsmReader, TruncatedAndCorruptedFilesNeverCrash) {
  const std::string simple = file_text("simple.tsm");
  int refused = 0;
  auto read = [&](const std::string& text) {
    try {
      infer_tspline(parse_tsm(text, "cut.tsm"), "cut.tsm");
    } catch (const InputError&) {
      ++refused;
    }
  };
  for (std::size_t size = 0; size < simple.size(); size += 3) read(simple.substr(0, size));
  for (std::size_t at = 200; at < simple.size(); at += 5)
    for (const char c : {'9', '-', ' ', '\n', 'x'}) {
      std::string text = simple;
      text[at] = c;
      read(text);
    }
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace nurbs
