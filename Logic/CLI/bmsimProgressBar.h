// bmsimProgressBar.h - a terminal progress bar on stderr for long steps.
#pragma once

#include <string>

namespace bm::cli {

class ProgressBar {
public:
  /// label: the step's name. Draws only when stderr is a terminal.
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  /// fraction in [0, 1]; returns true (never cancels).
  bool Update(double fraction);
  void Finish();

private:
  std::string Label_;
  bool Tty_ = false;
  int LastPercent_ = -1;
  bool Done_ = false;
};

} // namespace bm::cli
