// JSON parsing for files a user hands us: nesting depth bounded and duplicate keys refused while
// parsing, each as an InputError naming `origin`.
//
// Depth: nlohmann's parser is iterative, but dump(), comparisons and any recursive walk of the
// tree are not, so a file of 300000 nested brackets would overflow the stack later; refusing it
// during parsing means no deep tree ever exists. Duplicates: nlohmann keeps the last value of a
// repeated key, so `"degree_u": 3, "degree_u": 2` would silently mean 2.
#pragma once

#include <fmt/format.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "reference/validation.h"
#include "scenes/json_error.h"

namespace nurbs {

// A nurbs-scene/2 file nests 10 levels (document, surfaces, surface, trim, loops, loop, curves,
// curve, points, point).
inline constexpr int kMaxJsonDepth = 64;

namespace detail {

// Follows the parser's events to know the path of the value being read ("surfaces[0].degree_u")
// and the keys already seen in every open object.
class JsonPathTracker {
 public:
  explicit JsonPathTracker(std::string_view origin) : origin_(origin) {}

  bool operator()(int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        // `depth` counts the containers already open, so this one is level depth + 1.
        if (depth + 1 > kMaxJsonDepth)
          throw InputError(fmt::format("{}: {}: nesting deeper than {} levels", printable(origin_),
                                       path_text(), kMaxJsonDepth));
        open_.push_back(Container{event == Event::array_start, 0, {}, {}});
        break;
      case Event::key: {
        Container& object = open_.back();
        object.key = parsed.get<std::string>();
        if (!object.keys.insert(object.key).second)
          throw InputError(fmt::format("{}: {}: duplicate key (each key may appear once)",
                                       printable(origin_), path_text()));
        break;
      }
      case Event::object_end:
      case Event::array_end:
        open_.pop_back();
        element_done();
        break;
      case Event::value:
        element_done();
        break;
    }
    return true;
  }

  // The path of the value being read ("surfaces[0].degree_u"), keys JSON-escaped (ASCII) so a path
  // stays one line and cut short so it stays readable; "(document)" before the first container
  // opens.
  std::string path_text() const {
    std::string path;
    for (const Container& c : open_) {
      if (c.array) {
        path += fmt::format("[{}]", c.index);
      } else {
        std::string key =
            nlohmann::json(c.key).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
        key = key.substr(1, key.size() - 2);
        if (key.size() > kMaxKeyShown) key = key.substr(0, kMaxKeyShown - 3) + "...";
        path += path.empty() ? key : "." + key;
      }
    }
    return path.empty() ? "(document)" : path;
  }

 private:
  static constexpr std::size_t kMaxKeyShown = 40;

  struct Container {
    bool array;
    std::size_t index;  // arrays: the element being read
    std::string key;    // objects: the key being read
    std::unordered_set<std::string> keys;
  };

  void element_done() {
    if (!open_.empty() && open_.back().array) ++open_.back().index;
  }

  std::string_view origin_;
  std::vector<Container> open_;
};

}  // namespace detail

// Throws InputError "<origin>: not valid JSON at <path>: ..." for malformed text (and numbers
// out of double's range), "<origin>: <path>: nesting deeper than N levels", "<origin>: <path>:
// duplicate key".
inline nlohmann::json parse_json_strictly(std::string_view text, std::string_view origin) {
  detail::JsonPathTracker tracker(origin);
  try {
    return nlohmann::json::parse(
        text.begin(), text.end(),
        [&tracker](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
          return tracker(depth, event, parsed);
        });
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(fmt::format("{}: not valid JSON at {}: {}", printable(origin),
                                 tracker.path_text(), json_error_text(e)));
  }
}

}  // namespace nurbs
