#include "bmHapticDeviceModel.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace bm {

double PublishedMaxForceN(const std::string& model) {
  std::string m;
  for (char c : model)
    m += char(std::tolower((unsigned char)c));
  const auto has = [&](const char* s) { return m.find(s) != std::string::npos; };
  // Most specific names first ("touch x" before "touch", "high force" before "premium").
  if (has("premium") && (has("high force") || has("hf") || has("6dof")))
    return 37.5;
  if (has("premium") && has("3.0"))
    return 22.0;
  if (has("premium"))
    return 8.5;
  if (has("touch x") || has("desktop"))
    return 7.9;
  return DeviceLimits().maxForceN; // the Touch (PHANTOM Omni), or a model not known here
}

DeviceLimits CapToModel(DeviceLimits reported, const std::string& model) {
  const double cap = PublishedMaxForceN(model);
  if (!(std::isfinite(reported.maxForceN) && reported.maxForceN > 0))
    reported.maxForceN = cap;
  reported.maxForceN = std::min(reported.maxForceN, cap);
  return reported;
}

} // namespace bm
