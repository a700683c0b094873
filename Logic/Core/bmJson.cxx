#include "bmJson.h"

#include <istream>
#include <stdexcept>

namespace bm {

namespace {

struct TooDeep {};

template <class Input> nlohmann::json Parse(Input&& input, const std::string& what, int maxDepth) {
  if (maxDepth < 1)
    throw std::invalid_argument("ParseJson: depth limit " + std::to_string(maxDepth) +
                                " must be >= 1");
  // The callback sees each value's depth as it starts: the parse stops at the first level too
  // deep, before anything below it is read or built.
  const nlohmann::json::parser_callback_t limit =
      [maxDepth](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if ((event == nlohmann::json::parse_event_t::object_start ||
             event == nlohmann::json::parse_event_t::array_start) &&
            depth >= maxDepth)
          throw TooDeep{};
        return true;
      };
  try {
    return nlohmann::json::parse(std::forward<Input>(input), limit);
  } catch (const TooDeep&) {
    throw std::runtime_error(what + " is nested deeper than " + std::to_string(maxDepth) +
                             " levels (arrays and objects); refused");
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(what + " is not valid JSON: " + e.what());
  }
}

} // namespace

nlohmann::json ParseJson(std::string_view text, const std::string& what, int maxDepth) {
  return Parse(text, what, maxDepth);
}

nlohmann::json ParseJson(std::istream& in, const std::string& what, int maxDepth) {
  return Parse(in, what, maxDepth);
}

} // namespace bm
