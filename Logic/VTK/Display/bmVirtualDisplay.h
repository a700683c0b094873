// bmVirtualDisplay.h - an X display for rendering where there is none (CI, ssh, the demo).
//
// Debian's ParaView VTK renders only through GLX, so a render window needs an X server. When
// DISPLAY is unset, Ensure() starts a private Xvfb (`Xvfb -displayfd`, no TCP) and points this
// process's DISPLAY at it. The server dies with this process, however it ends: a keeper process
// (forked first, Xvfb its child) waits on a pipe whose write end only this process holds; when
// the process exits or is killed (SIGKILL included) the keeper reads end-of-file and stops Xvfb
// (SIGTERM, then reaped); Xvfb itself gets SIGKILL if the keeper is killed
// (prctl(PR_SET_PDEATHSIG), tied to the single-threaded keeper). When DISPLAY is set, nothing is
// started.
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
  VirtualDisplay(pid_t pid, int lifeFd, std::string name)
      : Pid_(pid), LifeFd_(lifeFd), Name_(std::move(name)) {}
  pid_t Pid_;  ///< the keeper process (Xvfb is its child)
  int LifeFd_; ///< write end of the keeper's pipe: closed, the keeper stops Xvfb
  std::string Name_;
};

} // namespace bm
