#include "bmExcludedHead.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace bm {

nlohmann::json ExcludedHeadToJson(const ExcludedHead& h) {
  nlohmann::json b = {
      {"centre_mm", h.centreMm}, {"radius_mm", h.radiusMm}, {"shell_mm", h.shellMm}};
  if (h.socketCentreMm) {
    b["socket_centre_mm"] = *h.socketCentreMm;
    b["socket_radius_mm"] = h.socketRadiusMm;
  }
  return b;
}

ExcludedHead ExcludedHeadFromJson(const nlohmann::json& j, const std::string& what) {
  const std::string shape =
      what + " must hold {\"centre_mm\": [x, y, z], \"radius_mm\": r, \"shell_mm\": s} with an "
             "optional \"socket_centre_mm\": [x, y, z] and \"socket_radius_mm\": rs (mm; 0 < r "
             "<= 200, r < rs <= 1000, 0 <= s <= 20)";
  auto point = [&](const nlohmann::json& v) {
    if (!v.is_array() || v.size() != 3)
      throw std::runtime_error(shape);
    std::array<double, 3> p{};
    for (size_t a = 0; a < 3; ++a) {
      if (!v[a].is_number() || !std::isfinite(v[a].get<double>()))
        throw std::runtime_error(shape);
      p[a] = v[a].get<double>();
    }
    return p;
  };
  auto number = [&](const char* key) {
    if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
      throw std::runtime_error(shape);
    return j[key].get<double>();
  };
  if (!j.is_object() || !j.contains("centre_mm"))
    throw std::runtime_error(shape);
  ExcludedHead h;
  h.centreMm = point(j["centre_mm"]);
  h.radiusMm = number("radius_mm");
  h.shellMm = number("shell_mm");
  if (j.contains("socket_centre_mm")) {
    h.socketCentreMm = point(j["socket_centre_mm"]);
    h.socketRadiusMm = number("socket_radius_mm");
    if (!(h.socketRadiusMm > h.radiusMm && h.socketRadiusMm <= 1000))
      throw std::runtime_error(shape);
  }
  if (!(h.radiusMm > 0 && h.radiusMm <= 200 && h.shellMm >= 0 && h.shellMm <= 20))
    throw std::runtime_error(shape);
  return h;
}

} // namespace bm
