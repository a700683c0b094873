// bmJson.h - JSON read from files and headers the user supplies (scenes, recordings' headers,
// coefficient files), parsed with a nesting limit: a document nested 100 000 deep parses, but
// the code that walks, copies or prints it recurses once per level and overflows the stack.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace bm {

/// Deepest nesting of arrays and objects accepted in any JSON the project reads (the scenes and
/// plans nest at most 6 deep).
constexpr int kMaxJsonDepth = 64;

/// Parses `text` as one JSON document. Throws std::runtime_error naming `what` (e.g. "scene file
/// 'x.json'") and the problem: "is nested deeper than 64 levels" (checked while parsing, before
/// the deep part is built), or "is not valid JSON: <the parser's message>".
nlohmann::json ParseJson(std::string_view text, const std::string& what,
                         int maxDepth = kMaxJsonDepth);
/// The same for the rest of a stream.
nlohmann::json ParseJson(std::istream& in, const std::string& what, int maxDepth = kMaxJsonDepth);

} // namespace bm
