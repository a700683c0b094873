// bmGlenoidPhantomGeometry.cxx - see bmGlenoidPhantomGeometry.h.
#include "bmGlenoidPhantomGeometry.h"

#include "bmPhantom.h"

namespace bmtest {

void WriteGlenoidDicom(const std::string& folder) {
  bm::WritePhantomSeries("glenoid", folder);
}

bool GlenoidIsBone(const std::array<double, 3>& p) {
  return bm::PhantomIsBone("glenoid", p);
}

void GlenoidFace(std::array<double, 3>& centre, std::array<double, 3>& axisOut) {
  const bm::PhantomInfo info = bm::GetPhantomInfo("glenoid");
  centre = info.centreMm;
  axisOut = info.axisOut;
}

} // namespace bmtest
