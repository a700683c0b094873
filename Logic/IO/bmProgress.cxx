#include "bmProgress.h"

#include <itkCommand.h>
#include <itkProcessObject.h>

#include <algorithm>
#include <memory>

namespace bm {

Progress Progress::Range(double a, double b) const {
  Progress p = *this;
  p.Lo_ = Lo_ + (Hi_ - Lo_) * a;
  p.Hi_ = Lo_ + (Hi_ - Lo_) * b;
  return p;
}

void Progress::operator()(double f, const std::string& stage) const {
  if (!Fn_)
    return;
  f = std::clamp(f, 0.0, 1.0);
  if (!Fn_(Lo_ + (Hi_ - Lo_) * f, stage))
    throw Cancelled();
}

namespace {
// ITK observer: forwards ProgressEvent, and on a cancel asks the filter to abort (ITK then throws
// ProcessAborted out of Update(), which RunFilter turns into Cancelled).
class ProgressObserver : public itk::Command {
public:
  using Self = ProgressObserver;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  Progress P;
  std::string Stage;
  bool CancelRequested = false;
  double Last = 0; // multi-threaded filters report out of order: only report forward
  void Execute(itk::Object* caller, const itk::EventObject& event) override {
    auto* po = dynamic_cast<itk::ProcessObject*>(caller);
    if (!po || !itk::ProgressEvent().CheckEvent(&event))
      return;
    double f = po->GetProgress();
    if (f <= Last)
      return;
    Last = f;
    try {
      P(f, Stage);
    } catch (const Cancelled&) {
      CancelRequested = true;
      po->AbortGenerateDataOn();
    }
  }
  void Execute(const itk::Object*, const itk::EventObject&) override {}
};
} // namespace

void Progress::Observe(itk::ProcessObject* filter, const std::string& stage) const {
  if (!Fn_)
    return;
  auto obs = ProgressObserver::New();
  obs->P = *this;
  obs->Stage = stage;
  filter->AddObserver(itk::ProgressEvent(), obs);
}

void RunFilter(itk::ProcessObject* filter, const Progress& progress, const std::string& stage) {
  progress(0.0, stage);
  progress.Observe(filter, stage);
  try {
    filter->Update();
  } catch (const itk::ProcessAborted&) {
    throw Cancelled();
  } catch (const itk::ExceptionObject& e) {
    if (filter->GetAbortGenerateData())
      throw Cancelled();
    throw std::runtime_error(stage + ": " + e.GetDescription());
  }
  if (filter->GetAbortGenerateData())
    throw Cancelled();
  filter->RemoveAllObservers();
  progress(1.0, stage);
}

} // namespace bm
