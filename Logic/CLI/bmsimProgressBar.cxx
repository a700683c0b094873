#include "bmsimProgressBar.h"

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace bm::cli {

ProgressBar::ProgressBar(std::string label)
    : Label_(std::move(label)), Tty_(::isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
  Finish();
}

bool ProgressBar::Update(double fraction) {
  const int pct = int(std::clamp(fraction, 0.0, 1.0) * 100.0);
  if (!Tty_ || pct == LastPercent_)
    return true;
  LastPercent_ = pct;
  const int width = 30, filled = pct * width / 100;
  std::fprintf(stderr, "\r%-24s [%s%s] %3d%%", Label_.c_str(),
               std::string(size_t(filled), '#').c_str(),
               std::string(size_t(width - filled), ' ').c_str(), pct);
  std::fflush(stderr);
  return true;
}

void ProgressBar::Finish() {
  if (Done_)
    return;
  Done_ = true;
  if (Tty_ && LastPercent_ >= 0)
    std::fprintf(stderr, "\n");
}

} // namespace bm::cli
