// bmHtmlEscape.h - text made safe inside HTML and SVG (element text and quoted attributes), for
// every report the module writes.
#pragma once

#include <string>

namespace bm {

/// s with &, <, > and " replaced by their character references.
inline std::string HtmlEscape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

} // namespace bm
