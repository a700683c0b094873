// bmGlenoidPhantomGeometry.h - the glenoid phantom for the reaming scene test, behind plain types:
// bmPhantom.h pulls in ITK (and its bundled Eigen 3.3), which must not meet the system Eigen 3.4
// of the machining logic in one translation unit.
#pragma once

#include <array>
#include <string>

namespace bmtest {

/// Writes the glenoid phantom CT as a DICOM series into `folder` (bm::WritePhantomSeries).
void WriteGlenoidDicom(const std::string& folder);
/// True when world point p (mm) is bone in the analytic glenoid phantom (bm::PhantomIsBone).
bool GlenoidIsBone(const std::array<double, 3>& pMm);
/// The analytic face centre (world mm) and outward axis of the glenoid phantom.
void GlenoidFace(std::array<double, 3>& centreMm, std::array<double, 3>& axisOut);

} // namespace bmtest
