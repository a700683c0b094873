#include "bmOpenCLRuntime.h"

#include <algorithm>
#include <cstdlib>
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
  // $BM_OPENCL_LANES / $BM_OPENCL_GROUPS stand for options left automatic (tuning on a new device).
  auto fromEnv = [](const char* name, int given) {
    const char* v = std::getenv(name);
    return given > 0 || !v || !*v ? given : std::atoi(v);
  };
  const int wantLanes = fromEnv("BM_OPENCL_LANES", o.lanes);
  const int wantGroups = fromEnv("BM_OPENCL_GROUPS", o.groups);
  lanes = wantLanes > 0 ? wantLanes : (gpu ? 128 : 1);
  if (lanes & (lanes - 1))
    throw std::runtime_error("OpenCL lanes must be a power of two");
  groups = wantGroups > 0 ? wantGroups : (gpu ? 1024 : 4 * std::max(1, info.computeUnits));
  if (o.int64Atomics == 1 && !info.int64Atomics)
    throw std::runtime_error("OpenCL device '" + info.name + "' lacks cl_khr_int64_base_atomics");
  int64Atomics = o.int64Atomics == 1 || (o.int64Atomics < 0 && gpu && info.int64Atomics);
  deviceHeldBone = o.deviceHeldBone;
}

std::string OpenCLRuntime::BuildOptions() const {
  std::string opts = int64Atomics ? "-DBM_INT64_ATOMICS" : "";
  if (!deviceHeldBone)
    opts += opts.empty() ? "-DBM_HOST_MIRROR" : " -DBM_HOST_MIRROR";
  return opts;
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
