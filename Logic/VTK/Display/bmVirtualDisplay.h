// bmVirtualDisplay.h - an X display for rendering where there is none (CI, ssh, the demo).
//
// Debian's ParaView VTK renders only through GLX, so a render window needs an X server. When
// DISPLAY is unset, Ensure() starts a private Xvfb (`Xvfb -displayfd`, no TCP) and points this
// process's DISPLAY at it; the server is stopped (SIGTERM, then reaped) when the process exits.
// When DISPLAY is set, nothing is started.
#pragma once

#include <memory>
#include <string>
#include <sys/types.h>

namespace bm {

class VirtualDisplay {
public:
  /// Starts Xvfb if DISPLAY is unset. Returns nullptr when a display already exists. Throws
  /// std::runtime_error naming the problem when Xvfb is missing or does not come up within
  /// timeoutS seconds (default 10 s).
  static std::unique_ptr<VirtualDisplay> Start(double timeoutS = 10.0);
  /// Process-wide: the first call starts a display if needed and keeps it until exit.
  static void Ensure();

  ~VirtualDisplay();
  VirtualDisplay(const VirtualDisplay&) = delete;
  VirtualDisplay& operator=(const VirtualDisplay&) = delete;
  /// The DISPLAY value, e.g. ":99".
  const std::string& Name() const { return Name_; }

private:
  VirtualDisplay(pid_t pid, std::string name) : Pid_(pid), Name_(std::move(name)) {}
  pid_t Pid_;
  std::string Name_;
};

} // namespace bm
