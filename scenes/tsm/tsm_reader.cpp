#include "scenes/tsm/tsm_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <optional>
#include <type_traits>
#include <vector>

#include "reference/error_text.h"
#include "reference/validation.h"
#include "scenes/scene_json.h"

namespace nurbs {
namespace {

// Compass directions as quarter turns counter-clockwise from +s.
enum Direction : int { kEast = 0, kNorth = 1, kWest = 2, kSouth = 3 };
constexpr int kStepS[4] = {1, 0, -1, 0};
constexpr int kStepT[4] = {0, 1, 0, -1};
constexpr const char* kDirectionNames[4] = {"EAST", "NORTH", "WEST", "SOUTH"};

// One record line: its 1-based number and whitespace-separated tokens (comment removed).
struct Record {
  int line = 0;
  std::vector<std::string_view> tokens;
};

struct Link {
  int prev, next, opp, vertex, face, edge, flag;
};
constexpr const char* kLinkFields[7] = {"prev", "next", "opp", "vertex", "face", "edge", "flag"};

struct Face {
  int link = -1;
};
struct Edge {
  int link = -1;
  double interval = 0;
};
struct Vertex {
  int link = -1;
  int direction = 0;  // of `link`, in the vertex's own frame
};
struct Grip {
  int vertex = -1;
  bool prime = false;
};
struct CompoundGrip {
  int vertex = -1;
  std::array<int, 4> dims{};  // extra knot lines toward N, W, S, E of the vertex's frame
  std::vector<int> grips;
};
struct ControlPoint {
  Point3 xyz{};
  double w = 1;
};

// A record slot: present, or deleted (the record type alone on its line).
template <typename T>
struct Slot {
  std::optional<T> value;
  int line = 0;
};

class TsmParser {
 public:
  TsmParser(std::string_view bytes, const std::string& origin) : origin_(origin) {
    split_lines(bytes);
  }

  TMesh parse();

 private:
  [[noreturn]] void fail(int line, const std::string& what, std::string_view value,
                         const std::string& rule) const {
    throw InputError(fmt::format("{}:{}: {} = {}: {}", printable(origin_), line, what,
                                 printable(value, kQuotedValueBytes), rule));
  }
  [[noreturn]] void fail_file(const std::string& message) const {
    throw InputError(fmt::format("{}: {}", printable(origin_), message));
  }

  void split_lines(std::string_view bytes);
  template <typename T>
  T number(const Record& r, std::size_t token, const std::string& field) const;
  int integer(const Record& r, std::size_t token, const std::string& field) const;
  double real(const Record& r, std::size_t token, const std::string& field) const;
  void expect_tokens(const Record& r, std::size_t count, const char* layout) const;
  void read_records();
  void check_references() const;
  void refuse_extraordinary_points() const;
  void lay_out_directions();
  void lay_out_positions();
  TMesh build_index_mesh() const;

  template <typename T>
  const T& at(const std::vector<Slot<T>>& slots, int index, int line, const std::string& what,
              const char* kind) const {
    if (index < 0 || static_cast<std::size_t>(index) >= slots.size() || !slots[index].value)
      fail(line, what, std::to_string(index),
           fmt::format("no such {} ({} records, deleted ones included)", kind, slots.size()));
    return *slots[index].value;
  }

  const std::string& origin_;
  std::vector<Record> records_;
  std::optional<int> degree_;
  bool bezier_ends_ = false;
  std::vector<Slot<Face>> faces_;
  std::vector<Slot<Edge>> edges_;
  std::vector<Slot<Vertex>> vertices_;
  std::vector<Slot<Link>> links_;
  std::vector<Slot<Grip>> grips_;
  std::vector<Slot<ControlPoint>> points_;
  std::vector<std::pair<CompoundGrip, int>> compounds_;  // with their line
  std::vector<int> link_direction_;                      // global, per link
  std::vector<std::array<double, 2>> position_;          // (s, t) per vertex
  int first_link_ = -1;                                  // laid out first, pointing east
};

void TsmParser::split_lines(std::string_view bytes) {
  int number = 0;
  while (!bytes.empty()) {
    const std::size_t end = std::min(bytes.find('\n'), bytes.size());
    std::string_view text = bytes.substr(0, end);
    bytes.remove_prefix(std::min(end + 1, bytes.size()));
    ++number;
    if (number == 1) {
      if (text.substr(0, 7) != "#TS0200")
        fail(1, "header", text.substr(0, 16),
             "not a Rhino T-Splines file (the first line must start with #TS0200)");
      continue;
    }
    text = text.substr(0, text.find('#'));
    Record r{number, {}};
    for (std::size_t i = 0; i < text.size();) {
      while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
      std::size_t j = i;
      while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
      if (j > i) r.tokens.push_back(text.substr(i, j - i));
      i = j;
    }
    if (!r.tokens.empty()) records_.push_back(std::move(r));
  }
  if (number == 0) fail_file("empty file: not a Rhino T-Splines #TS0200 file");
}

template <typename T>
T TsmParser::number(const Record& r, std::size_t token, const std::string& field) const {
  if (token >= r.tokens.size())
    fail(r.line, fmt::format("{} {}", r.tokens[0], field), "(missing)", "truncated record");
  const std::string_view t = r.tokens[token];
  T value{};
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
  bool ok = error == std::errc() && end == t.data() + t.size();
  if constexpr (std::is_floating_point_v<T>) ok = ok && std::isfinite(value);
  if (!ok)
    fail(r.line, fmt::format("{} {}", r.tokens[0], field), t,
         std::is_floating_point_v<T> ? "not a finite number" : "not an integer");
  return value;
}

int TsmParser::integer(const Record& r, std::size_t token, const std::string& field) const {
  return number<int>(r, token, field);
}

double TsmParser::real(const Record& r, std::size_t token, const std::string& field) const {
  return number<double>(r, token, field);
}

void TsmParser::expect_tokens(const Record& r, std::size_t count, const char* layout) const {
  if (r.tokens.size() < count)
    fail(r.line, std::string(r.tokens[0]), fmt::format("{} field(s)", r.tokens.size() - 1),
         fmt::format("truncated record: expected '{}'", layout));
}

void TsmParser::read_records() {
  const std::size_t limit = static_cast<std::size_t>(kMaxTSplineControlPoints) * 8;
  if (records_.size() > limit)
    fail_file(fmt::format("{} records exceed the limit of {}", records_.size(), limit));
  for (const Record& r : records_) {
    const std::string_view type = r.tokens[0];
    const bool deleted = r.tokens.size() == 1;
    if (type == "degree") {
      expect_tokens(r, 2, "degree N");
      degree_ = integer(r, 1, "N");
    } else if (type == "force-bezier-end-conditions") {
      expect_tokens(r, 2, "force-bezier-end-conditions 0|1");
      bezier_ends_ = integer(r, 1, "value") != 0;
    } else if (type == "f") {
      faces_.push_back(
          {deleted ? std::nullopt : std::optional<Face>(Face{integer(r, 1, "link")}), r.line});
    } else if (type == "e") {
      if (deleted) {
        edges_.push_back({std::nullopt, r.line});
        continue;
      }
      expect_tokens(r, 3, "e LINK INTERVAL");
      const Edge e{integer(r, 1, "link"), real(r, 2, "interval")};
      if (e.interval < 0) fail(r.line, "e interval", r.tokens[2], "knot intervals must be >= 0");
      edges_.push_back({e, r.line});
    } else if (type == "v") {
      if (deleted) {
        vertices_.push_back({std::nullopt, r.line});
        continue;
      }
      expect_tokens(r, 3, "v LINK DIRECTION");
      const auto* name =
          std::find(std::begin(kDirectionNames), std::end(kDirectionNames), r.tokens[2]);
      if (name == std::end(kDirectionNames))
        fail(r.line, "v direction", r.tokens[2], "must be EAST, NORTH, WEST or SOUTH");
      vertices_.push_back(
          {Vertex{integer(r, 1, "link"), static_cast<int>(name - kDirectionNames)}, r.line});
    } else if (type == "l") {
      if (deleted) {
        links_.push_back({std::nullopt, r.line});
        continue;
      }
      expect_tokens(r, 8, "l PREV NEXT OPP VERTEX FACE EDGE FLAG");
      int f[7];
      for (int i = 0; i < 7; ++i) f[i] = integer(r, 1 + i, kLinkFields[i]);
      links_.push_back({Link{f[0], f[1], f[2], f[3], f[4], f[5], f[6]}, r.line});
    } else if (type == "ec") {
      if (!deleted && r.tokens.size() > 2 && integer(r, 2, "condition") != 0)
        fail(r.line, "ec condition", r.tokens[2],
             "edge conditions other than 0 (creases?) are not supported");
    } else if (type == "0g") {
      if (deleted) {
        points_.push_back({std::nullopt, r.line});
        continue;
      }
      expect_tokens(r, 5, "0g X Y Z W");
      const ControlPoint p{{real(r, 1, "x"), real(r, 2, "y"), real(r, 3, "z")}, real(r, 4, "w")};
      if (!(p.w > 0)) fail(r.line, "0g w", r.tokens[4], "weights must be > 0");
      points_.push_back({p, r.line});
    } else if (type == "0m" && r.tokens.size() >= 2) {
      const std::string_view what = r.tokens[1];
      if (what == "gvp" || what == "gv") {
        expect_tokens(r, 3, "0m gv[p] VERTEX");
        grips_.push_back({Grip{integer(r, 2, "vertex"), what == "gvp"}, r.line});
      } else if (what == "cg") {
        expect_tokens(r, 8, "0m cg VERTEX 4 D0 D1 D2 D3 GRIP...");
        CompoundGrip cg;
        cg.vertex = integer(r, 2, "vertex");
        const int valence = integer(r, 3, "valence");
        if (valence != 4)
          fail(r.line, "0m cg valence", r.tokens[3],
               "only valence-4 grip layouts are supported (star point)");
        int expected = 0;
        for (int k = 0; k < 4; ++k) {
          cg.dims[k] = integer(r, 4 + k, fmt::format("d{}", k));
          if (cg.dims[k] < 0 || cg.dims[k] > kMaxDegree)
            fail(r.line, fmt::format("0m cg d{}", k), r.tokens[4 + k],
                 fmt::format("must be in 0..{}", kMaxDegree));
        }
        for (int k = 0; k < 4; ++k) expected += cg.dims[k] * (cg.dims[(k + 1) % 4] + 1);
        for (std::size_t t = 8; t < r.tokens.size(); ++t)
          cg.grips.push_back(integer(r, t, fmt::format("grip[{}]", t - 8)));
        if (static_cast<int>(cg.grips.size()) != expected)
          fail(r.line, "0m cg grips", std::to_string(cg.grips.size()),
               fmt::format("dims {} {} {} {} need {} grips", cg.dims[0], cg.dims[1], cg.dims[2],
                           cg.dims[3], expected));
        compounds_.push_back({std::move(cg), r.line});
      }
    }
    // Anything else (cap-type, units, tol, ver, odd-grip-map, 100001uv, 50000grip, 105...) does
    // not shape the surface.
  }
  if (!degree_) fail_file("no 'degree' record");
}

void TsmParser::check_references() const {
  for (std::size_t i = 0; i < links_.size(); ++i) {
    if (!links_[i].value) continue;
    const Link& l = *links_[i].value;
    const int line = links_[i].line;
    for (int index : {l.prev, l.next, l.opp}) at(links_, index, line, "l half-edge", "half-edge");
    at(vertices_, l.vertex, line, "l vertex", "vertex");
    at(edges_, l.edge, line, "l edge", "edge");
    if (l.face != -1) at(faces_, l.face, line, "l face", "face");
    if (links_[l.next].value->prev != static_cast<int>(i) ||
        links_[l.opp].value->opp != static_cast<int>(i))
      fail(line, "l next/opp", fmt::format("{}/{}", l.next, l.opp),
           fmt::format("half-edge {} is not the prev/opp of its next/opp", i));
  }
  auto back_reference = [&](const auto& slots, const char* kind, auto field) {
    for (std::size_t i = 0; i < slots.size(); ++i)
      if (slots[i].value) {
        const Link& l = at(links_, slots[i].value->link, slots[i].line,
                           fmt::format("{} link", kind), "half-edge");
        if (field(l) != static_cast<int>(i))
          fail(slots[i].line, fmt::format("{} link", kind), std::to_string(slots[i].value->link),
               fmt::format("that half-edge belongs to {} {}, not {}", kind, field(l), i));
      }
  };
  back_reference(faces_, "f", [](const Link& l) { return l.face; });
  back_reference(edges_, "e", [](const Link& l) { return l.edge; });
  back_reference(vertices_, "v", [](const Link& l) { return l.vertex; });
}

void TsmParser::refuse_extraordinary_points() const {
  std::vector<int> angle(vertices_.size(), 0), valence(vertices_.size(), 0);
  std::vector<bool> boundary(vertices_.size(), false);
  for (const auto& slot : links_) {
    if (!slot.value) continue;
    const Link& l = *slot.value;
    ++valence[l.vertex];
    if (l.face < 0)
      boundary[l.vertex] = true;
    else
      angle[l.vertex] += l.flag != 0 ? 180 : 90;
  }
  for (std::size_t v = 0; v < vertices_.size(); ++v) {
    if (!vertices_[v].value) continue;
    const int line = vertices_[v].line;
    const std::string what = fmt::format("vertex {}", v);
    if (!boundary[v] && angle[v] != 360)
      fail(line, what, fmt::format("valence {}", valence[v]),
           fmt::format("its face corners add up to {} degrees, not 360: an extraordinary (star) "
                       "point; T-splines with star points are not supported",
                       angle[v]));
    if (boundary[v] && angle[v] != 90 && angle[v] != 180)
      fail(line, what, fmt::format("valence {}", valence[v]),
           fmt::format("a boundary vertex whose face corners add up to {} degrees (a concave "
                       "corner or a boundary star point): only rectangular domains are supported",
                       angle[v]));
  }
}

// Every half-edge's compass direction: face loops run counter-clockwise, turning a quarter left
// at each corner (flag 0), straight on through a vertex inside the side; a half-edge and its
// opposite point opposite ways.
void TsmParser::lay_out_directions() {
  link_direction_.assign(links_.size(), -1);
  const auto first_face =
      std::find_if(faces_.begin(), faces_.end(), [](const auto& f) { return f.value.has_value(); });
  if (first_face == faces_.end()) fail_file("no faces");
  first_link_ = first_face->value->link;
  std::deque<int> pending{first_link_};
  link_direction_[first_face->value->link] = kEast;
  auto assign = [&](int link, int direction, int from_line) {
    if (link_direction_[link] < 0) {
      link_direction_[link] = direction;
      pending.push_back(link);
    } else if (link_direction_[link] != direction) {
      fail(from_line, fmt::format("l {} direction", link), kDirectionNames[direction],
           fmt::format("already laid out {}: the mesh does not unfold into the plane (a closed "
                       "surface or a star point)",
                       kDirectionNames[link_direction_[link]]));
    }
  };
  while (!pending.empty()) {
    const int start = pending.front();
    pending.pop_front();
    const Link& first = *links_[start].value;
    assign(first.opp, (link_direction_[start] + 2) % 4, links_[start].line);
    if (first.face < 0) continue;
    int corners = first.flag == 0 ? 1 : 0, steps = 0, link = start;
    int direction = link_direction_[start];
    while ((link = links_[link].value->next) != start) {
      if (++steps > static_cast<int>(links_.size()))
        fail(links_[start].line, "l next", std::to_string(first.next), "face loop does not close");
      const Link& l = *links_[link].value;
      if (l.flag == 0) {
        direction = (direction + 1) % 4;
        ++corners;
      }
      assign(link, direction, links_[link].line);
    }
    if (corners != 4)
      fail(faces_[first.face].line, fmt::format("face {}", first.face),
           fmt::format("{} corners", corners), "faces must be rectangles (4 corners)");
  }
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].value && link_direction_[i] < 0)
      fail(links_[i].line, fmt::format("l {}", i), "unreached",
           "the mesh is not connected: only one T-spline surface per file is supported");
}

// (s, t) of every vertex, walking the knot intervals from the first face's first vertex.
void TsmParser::lay_out_positions() {
  position_.assign(vertices_.size(), {NAN, NAN});
  std::vector<std::vector<int>> outgoing(vertices_.size());
  double total = 0;
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].value) outgoing[links_[i].value->vertex].push_back(static_cast<int>(i));
  for (const auto& e : edges_)
    if (e.value) total += e.value->interval;
  const double tolerance = 1e-9 * std::max(total, 1.0);
  const int start = links_[first_link_].value->vertex;
  position_[start] = {0, 0};
  std::deque<int> pending{start};
  while (!pending.empty()) {
    const int a = pending.front();
    pending.pop_front();
    for (int link : outgoing[a]) {
      const Link& l = *links_[link].value;
      const int b = links_[l.next].value->vertex;
      const double interval = edges_[l.edge].value->interval;
      const int d = link_direction_[link];
      const std::array<double, 2> p{position_[a][0] + interval * kStepS[d],
                                    position_[a][1] + interval * kStepT[d]};
      if (std::isnan(position_[b][0])) {
        position_[b] = p;
        pending.push_back(b);
      } else if (std::fabs(position_[b][0] - p[0]) > tolerance ||
                 std::fabs(position_[b][1] - p[1]) > tolerance) {
        fail(links_[link].line, fmt::format("vertex {} position", b),
             fmt::format("({}, {}) and ({}, {})", position_[b][0], position_[b][1], p[0], p[1]),
             "knot intervals do not close up around the faces (inconsistent intervals or a "
             "closed surface)");
      }
    }
  }
  for (std::size_t v = 0; v < vertices_.size(); ++v)
    if (vertices_[v].value && std::isnan(position_[v][0]))
      fail(vertices_[v].line, fmt::format("vertex {}", v), "unreached",
           "not connected to the rest of the mesh");
  // The faces must tile the bounding rectangle once: no hole, no face folded over another.
  std::array<double, 4> box{INFINITY, -INFINITY, INFINITY, -INFINITY};
  double area = 0;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    if (!faces_[f].value) continue;
    std::array<double, 4> face{INFINITY, -INFINITY, INFINITY, -INFINITY};
    int link = faces_[f].value->link;
    do {
      const auto& p = position_[links_[link].value->vertex];
      face = {std::min(face[0], p[0]), std::max(face[1], p[0]), std::min(face[2], p[1]),
              std::max(face[3], p[1])};
      link = links_[link].value->next;
    } while (link != faces_[f].value->link);
    area += (face[1] - face[0]) * (face[3] - face[2]);
    box = {std::min(box[0], face[0]), std::max(box[1], face[1]), std::min(box[2], face[2]),
           std::max(box[3], face[3])};
  }
  const double box_area = (box[1] - box[0]) * (box[3] - box[2]);
  if (std::fabs(area - box_area) > tolerance * std::max(box_area, 1.0))
    fail_file(
        fmt::format("the faces cover an area of {} in (s, t), their bounding rectangle {}: "
                    "a hole or overlapping faces; only rectangular domains are supported",
                    area, box_area));
}

// Distinct values (within `tolerance`) of xs, ascending; index of each x's cluster.
std::vector<int> cluster(const std::vector<double>& xs, double tolerance,
                         std::vector<double>& values) {
  std::vector<double> sorted;
  for (double x : xs)
    if (!std::isnan(x)) sorted.push_back(x);
  std::sort(sorted.begin(), sorted.end());
  for (double x : sorted)
    if (values.empty() || x - values.back() > tolerance) values.push_back(x);
  std::vector<int> id(xs.size(), -1);
  for (std::size_t i = 0; i < xs.size(); ++i)
    if (!std::isnan(xs[i]))
      id[i] = static_cast<int>(std::lower_bound(values.begin(), values.end(), xs[i] - tolerance) -
                               values.begin());
  return id;
}

TMesh TsmParser::build_index_mesh() const {
  const std::size_t nv = vertices_.size();
  // Extra knot lines toward each global direction, and where each grip sits (offset from its
  // vertex's own point, in global index steps).
  std::vector<std::array<int, 4>> extent(nv, {0, 0, 0, 0});
  std::vector<std::array<int, 2>> offset(grips_.size(), {0, 0});
  std::vector<bool> placed(grips_.size(), false);
  for (std::size_t g = 0; g < grips_.size(); ++g)
    if (grips_[g].value && grips_[g].value->prime) placed[g] = true;
  for (const auto& [cg, line] : compounds_) {
    const Vertex& v = at(vertices_, cg.vertex, line, "0m cg vertex", "vertex");
    const int rotation = (link_direction_[v.link] - v.direction + 4) % 4;
    auto global = [&](int k) { return (kNorth + k + rotation) % 4; };
    for (int k = 0; k < 4; ++k) extent[cg.vertex][global(k)] = cg.dims[k];
    std::size_t next = 0;
    for (int k = 0; k < 4; ++k)
      for (int a = 1; a <= cg.dims[k]; ++a)
        for (int b = 0; b <= cg.dims[(k + 1) % 4]; ++b) {
          const int g = cg.grips[next++];
          const Grip& grip = at(grips_, g, line, "0m cg grip", "grip");
          if (grip.vertex != cg.vertex || grip.prime)
            fail(line, "0m cg grip", std::to_string(g),
                 fmt::format("that grip belongs to vertex {}{}", grip.vertex,
                             grip.prime ? " as its own point" : ""));
          const int d0 = global(k), d1 = global(k + 1);
          offset[g] = {a * kStepS[d0] + b * kStepS[d1], a * kStepT[d0] + b * kStepT[d1]};
          placed[g] = true;
        }
  }
  // Index lines: each distinct s value becomes west + 1 + east columns of that knot value.
  std::vector<double> s_of(nv, NAN), t_of(nv, NAN), s_values, t_values;
  for (std::size_t v = 0; v < nv; ++v)
    if (vertices_[v].value) {
      s_of[v] = position_[v][0];
      t_of[v] = position_[v][1];
    }
  const double tolerance = 1e-9;
  const std::vector<int> s_id = cluster(s_of, tolerance, s_values);
  const std::vector<int> t_id = cluster(t_of, tolerance, t_values);
  auto lines = [&](const std::vector<int>& id, std::size_t count, int low, int high,
                   const std::vector<double>& values, std::vector<double>& knots) {
    std::vector<int> before(count, 0), after(count, 0), first(count, 0);
    for (std::size_t v = 0; v < nv; ++v)
      if (id[v] >= 0) {
        before[id[v]] = std::max(before[id[v]], extent[v][low]);
        after[id[v]] = std::max(after[id[v]], extent[v][high]);
      }
    for (std::size_t c = 0; c < count; ++c) {
      first[c] = static_cast<int>(knots.size()) + before[c];
      knots.insert(knots.end(), static_cast<std::size_t>(before[c] + 1 + after[c]), values[c]);
    }
    return first;
  };
  TMesh mesh;
  mesh.name = std::filesystem::path(origin_).stem().string();
  mesh.degree_s = mesh.degree_t = *degree_;
  const std::vector<int> column =
      lines(s_id, s_values.size(), kWest, kEast, s_values, mesh.knots_s);
  const std::vector<int> row = lines(t_id, t_values.size(), kSouth, kNorth, t_values, mesh.knots_t);

  // Grip g is control point g; deleted grips (vertex -1) pair with deleted points.
  if (grips_.size() != points_.size())
    fail_file(fmt::format("{} grip records (0m gv/gvp) but {} control points (0g)", grips_.size(),
                          points_.size()));
  std::map<std::array<int, 3>, int> vertex_at;  // (vertex, ds, dt) -> mesh vertex
  for (std::size_t g = 0; g < grips_.size(); ++g) {
    if (!grips_[g].value || grips_[g].value->vertex < 0) {
      if (points_[g].value)
        fail(points_[g].line, fmt::format("0g (control point {})", g), "present",
             "its grip record is deleted (vertex -1)");
      continue;
    }
    const Grip& grip = *grips_[g].value;
    const int line = grips_[g].line;
    at(vertices_, grip.vertex, line, "0m gv vertex", "vertex");
    if (!placed[g])
      fail(line, fmt::format("grip {}", g), std::to_string(grip.vertex),
           "an extra point of its vertex that no '0m cg' record places");
    if (!points_[g].value)
      fail(points_[g].line, fmt::format("0g (control point {})", g), "(deleted)",
           "the control point of a live grip");
    const int v = grip.vertex;
    const int i = column[s_id[v]] + offset[g][0], j = row[t_id[v]] + offset[g][1];
    vertex_at[{v, offset[g][0], offset[g][1]}] = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back({i, j});
    mesh.points.push_back(points_[g].value->xyz);
    mesh.weights.push_back(points_[g].value->w);
  }
  auto find = [&](int v, int ds, int dt) {
    const auto it = vertex_at.find({v, ds, dt});
    return it == vertex_at.end() ? -1 : it->second;
  };
  auto connect = [&](int a, int b) {
    if (a >= 0 && b >= 0) mesh.edges.push_back({a, b});
  };
  // Within a vertex's block of points: the grid edges between its repeated knot lines.
  for (std::size_t v = 0; v < nv; ++v) {
    const auto& e = extent[v];
    for (int ds = -e[kWest]; ds <= e[kEast]; ++ds)
      for (int dt = -e[kSouth]; dt <= e[kNorth]; ++dt) {
        const int here = find(static_cast<int>(v), ds, dt);
        if (ds < e[kEast]) connect(here, find(static_cast<int>(v), ds + 1, dt));
        if (dt < e[kNorth]) connect(here, find(static_cast<int>(v), ds, dt + 1));
      }
  }
  // Each edge of the Rhino mesh, on every repeated line its two ends share.
  for (const auto& slot : edges_) {
    if (!slot.value) continue;
    const Link& l = *links_[slot.value->link].value;
    int a = l.vertex, b = links_[l.next].value->vertex, d = link_direction_[slot.value->link];
    if (d == kWest || d == kSouth) {
      std::swap(a, b);
      d = (d + 2) % 4;
    }
    const int side_low = d == kEast ? kSouth : kWest, side_high = d == kEast ? kNorth : kEast;
    const int from = std::max(-extent[a][side_low], -extent[b][side_low]);
    const int to = std::min(extent[a][side_high], extent[b][side_high]);
    for (int x = from; x <= to; ++x) {
      if (d == kEast)
        connect(find(a, extent[a][kEast], x), find(b, -extent[b][kWest], x));
      else
        connect(find(a, x, extent[a][kNorth]), find(b, x, -extent[b][kSouth]));
    }
  }
  return mesh;
}

TMesh TsmParser::parse() {
  read_records();
  check_references();
  refuse_extraordinary_points();
  lay_out_directions();
  lay_out_positions();
  TMesh mesh = build_index_mesh();
  validate_tmesh(mesh, origin_);
  return mesh;
}

}  // namespace

TMesh parse_tsm(std::string_view bytes, const std::string& origin) {
  return TsmParser(bytes, origin).parse();
}

TMesh load_tsm_file(const std::string& path) {
  return parse_tsm(read_input_file(path, "T-spline"), path);
}

}  // namespace nurbs
