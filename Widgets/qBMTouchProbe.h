// qBMTouchProbe.h - asks once, off the GUI thread, whether a Touch (OpenHaptics) can be used.
//
// start() runs the probe function on a worker thread and returns at once; the answer ("" when
// the Touch is ready, else why not) arrives as finished(), delivered queued to the GUI thread.
// The destructor waits for the worker (a probe is bounded by the probe function's own timeout),
// so no probe outlives the panel that asked. The default probe is bm::ProbeTouch()
// (Logic/Session/bmTouchProbe.h): the library checked, the device opened and its servo loop run
// at zero force in a child process, at most kTimeoutS; a library that crashes or hangs ends only
// the child, and the answer names the step.
#pragma once

#include <QObject>
#include <QString>

#include <functional>
#include <string>
#include <thread>

class qBMTouchProbe : public QObject {
  Q_OBJECT

public:
  /// What a probe runs: returns "" when a Touch can be used, else why not.
  using ProbeFunction = std::function<std::string()>;
  /// How long the default probe may take, s.
  static constexpr double kTimeoutS = 5.0;
  explicit qBMTouchProbe(QObject* parent = nullptr);
  /// Joins the worker if a probe is still running.
  ~qBMTouchProbe() override;

  /// Replaces the probe function (tests: a slow or failing probe). Ignored while running.
  void setProbeFunction(ProbeFunction probe);
  /// Starts a probe on the worker thread; does nothing while one runs.
  void start();
  /// Whether a probe is running.
  bool isRunning() const { return this->Running; }

Q_SIGNALS:
  /// The probe's answer: "" when the Touch is ready, else why not (on the GUI thread).
  void finished(const QString& status);

private:
  Q_DISABLE_COPY(qBMTouchProbe);
  ProbeFunction Probe;
  std::thread Worker;
  bool Running = false;
};
