#include "bmOpenCLRuntime.h"

#include <algorithm>
#include <stdexcept>

namespace bm {

OpenCLRuntime::OpenCLRuntime(const OpenCLOptions& o) {
  device = ChooseOpenCLDevice(o.device, &info);
  try {
    context = cl::Context(device);
    queue = cl::CommandQueue(context, device);
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL device '" + info.name +
                             "' could not be opened: " + DescribeOpenCLError(e));
  }
  const bool gpu = info.type == "gpu";
  lanes = o.lanes > 0 ? o.lanes : (gpu ? 128 : 1);
  if (lanes & (lanes - 1))
    throw std::runtime_error("OpenCL lanes must be a power of two");
  groups = o.groups > 0 ? o.groups : (gpu ? 4096 : 4 * std::max(1, info.computeUnits));
  if (o.int64Atomics == 1 && !info.int64Atomics)
    throw std::runtime_error("OpenCL device '" + info.name + "' lacks cl_khr_int64_base_atomics");
  int64Atomics = o.int64Atomics == 1 || (o.int64Atomics < 0 && gpu && info.int64Atomics);
}

std::string OpenCLRuntime::BuildOptions() const {
  return int64Atomics ? "-DBM_INT64_ATOMICS" : "";
}

cl::Buffer OpenCLRuntime::Upload(const void* data, size_t bytes, cl_mem_flags flags) {
  bytes = std::max<size_t>(bytes, 8);
  cl::Buffer b(context, flags, bytes);
  if (data)
    queue.enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
  deviceBytes += bytes;
  return b;
}

FrameInput OpenCLRuntime::WarmUpFrame() {
  FrameInput idle;
  idle.position = Eigen::Vector3d(1e9, 1e9, 1e9);
  idle.motion = Eigen::Vector3d(0, 0, -1e-6);
  return idle;
}

} // namespace bm
