// bmProgress.h - progress reporting and cancellation for long IO steps (reading a CT, segmenting,
// resampling, writing). One small callback: it gets the overall fraction done in [0, 1] and the
// name of the current stage, and returns false to cancel. The command line prints it as a bar; the
// GUI panel feeds the same callback to its progress widget.
//
// A step that sees a cancel throws bm::Cancelled, so no caller can mistake a half-done result for a
// finished one (and nothing is written: outputs are written only after the whole step succeeded).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace itk {
class ProcessObject;
}

namespace bm {

/// fraction in [0, 1] of the whole operation; stage = short human-readable name ("reading DICOM").
/// Return false to cancel. Called from the thread that runs the operation.
using ProgressFn = std::function<bool(double fraction, const std::string& stage)>;

/// Thrown when the progress callback asked to cancel.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled by the user") {}
};

/// A view of a ProgressFn restricted to a sub-range [lo, hi] of the whole operation, so a step can
/// report its own 0..1 without knowing where it sits. Default-constructed: reports nowhere.
class Progress {
public:
  Progress() = default;
  explicit Progress(ProgressFn fn) : Fn_(std::move(fn)) {}
  /// The part [a, b] (fractions of this range) as its own 0..1 range.
  Progress Range(double a, double b) const;
  /// Report fraction f (0..1 of this range) of `stage`; throws Cancelled if the callback says so.
  void operator()(double f, const std::string& stage) const;
  /// Report through an ITK filter's ProgressEvent while it runs; a cancel aborts the filter and
  /// Update() then throws Cancelled. Call before filter->Update(); use RunFilter() for both.
  void Observe(itk::ProcessObject* filter, const std::string& stage) const;
  bool Active() const { return bool(Fn_); }

private:
  ProgressFn Fn_;
  double Lo_ = 0, Hi_ = 1;
};

/// Run filter->Update() reporting through `progress`; turns an ITK abort into Cancelled and any
/// other ITK exception into std::runtime_error prefixed with `stage`.
void RunFilter(itk::ProcessObject* filter, const Progress& progress, const std::string& stage);

} // namespace bm
