#include "bmOpenCLBackend.h"

#include <memory>

#include "bmEngineFactory.h"
#include "bmOpenCLEngine.h"
#include "bmOpenCLZhengEngine.h"

namespace bm {

void RegisterOpenCLBackend() {
  RegisterBackend("opencl", [](const EngineContext& c) -> std::unique_ptr<Engine> {
    OpenCLOptions o;
    o.device = c.device;
    o.deviceHeldBone = c.deviceHeldBone;
    if (c.model.GetMethod() == Method::Zheng)
      return std::make_unique<OpenCLZhengEngine>(c.bone, c.tool, c.shell, c.model, o);
    return std::make_unique<OpenCLEngine>(c.bone, c.tool, c.shell, c.model, o);
  });
}

} // namespace bm
