// vtkBMSessionSource's force scale (tool N per device N): 0 by default (the device's own), a
// scale in range starts a session, one outside [0.001, 1000] is refused by Start() naming it.
#include "vtkBMSessionSource.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

#include <string>

namespace {
/// A short mouse-proxy drilling session (64 / 128: coarse and fast), frames back to back.
void Configure(vtkBMSessionSource* s) {
  s->SetScene("drilling");
  s->SetVoxmapResolution(64);
  s->SetShellResolution(128);
  s->SetDeviceType(vtkBMSessionSource::MOUSE);
  s->RealTimeOff();
  s->SetMaxFrames(1);
}
} // namespace

TEST(SessionSource, ForceScaleDefaultsToTheDevicesAndIsChecked) {
  vtkNew<vtkBMSessionSource> s;
  EXPECT_EQ(s->GetForceScale(), 0.0);
  Configure(s);
  s->SetForceScale(5000);
  EXPECT_FALSE(s->Start());
  const std::string error = s->GetLastError();
  EXPECT_NE(error.find("force scale"), std::string::npos) << error;
  EXPECT_NE(error.find("5000"), std::string::npos) << error;
  s->SetForceScale(2);
  EXPECT_TRUE(s->Start()) << s->GetLastError();
  s->Stop();
}
