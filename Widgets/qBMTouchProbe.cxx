// qBMTouchProbe.cxx - see qBMTouchProbe.h.
#include "qBMTouchProbe.h"

#include "bmTouchProbe.h"

#include <QMetaObject>

#include <exception>

qBMTouchProbe::qBMTouchProbe(QObject* parent)
    : QObject(parent), Probe([]() { return bm::ProbeTouch(kTimeoutS).message; }) {}

qBMTouchProbe::~qBMTouchProbe() {
  if (this->Worker.joinable())
    this->Worker.join();
}

void qBMTouchProbe::setProbeFunction(ProbeFunction probe) {
  if (!this->Running && probe)
    this->Probe = std::move(probe);
}

void qBMTouchProbe::start() {
  if (this->Running)
    return;
  if (this->Worker.joinable())
    this->Worker.join(); // the previous probe has answered
  this->Running = true;
  this->Worker = std::thread([this, probe = this->Probe]() {
    std::string status;
    try {
      status = probe();
    } catch (const std::exception& e) {
      status = std::string("touch probe failed: ") + e.what();
    } catch (...) {
      status = "touch probe failed";
    }
    // Queued: runs on this object's (the GUI) thread. The destructor joins this worker first, so
    // the object is alive when the call is posted; a call still queued at destruction is dropped.
    QMetaObject::invokeMethod(
        this,
        [this, answer = QString::fromStdString(status)]() {
          this->Running = false;
          Q_EMIT this->finished(answer);
        },
        Qt::QueuedConnection);
  });
}
