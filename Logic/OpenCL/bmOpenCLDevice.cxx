#include "bmOpenCLDevice.h"

#include <cstdlib>
#include <stdexcept>

#include "bmKernelSources.h"

namespace bm {

namespace {

OpenCLDeviceInfo Describe(const cl::Platform& p, const cl::Device& d, int index) {
  OpenCLDeviceInfo i;
  i.index = index;
  i.platform = p.getInfo<CL_PLATFORM_NAME>();
  i.name = d.getInfo<CL_DEVICE_NAME>();
  const cl_device_type t = d.getInfo<CL_DEVICE_TYPE>();
  i.type = (t & CL_DEVICE_TYPE_GPU)           ? "gpu"
           : (t & CL_DEVICE_TYPE_CPU)         ? "cpu"
           : (t & CL_DEVICE_TYPE_ACCELERATOR) ? "accelerator"
                                              : "other";
  i.version = d.getInfo<CL_DEVICE_VERSION>();
  i.computeUnits = int(d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
  i.globalMemoryBytes = size_t(d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>());
  const std::string ext = d.getInfo<CL_DEVICE_EXTENSIONS>();
  i.fp64 = ext.find("cl_khr_fp64") != std::string::npos;
  i.int64Atomics = ext.find("cl_khr_int64_base_atomics") != std::string::npos;
  return i;
}

struct Found {
  cl::Device device;
  OpenCLDeviceInfo info;
};

std::vector<Found> AllDevices() {
  std::vector<Found> out;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    return out; // CL_PLATFORM_NOT_FOUND_KHR: no ICD
  }
  for (const auto& p : platforms) {
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;
    }
    for (const auto& d : devices)
      out.push_back({d, Describe(p, d, int(out.size()))});
  }
  return out;
}

} // namespace

std::vector<OpenCLDeviceInfo> ListOpenCLDevices() {
  std::vector<OpenCLDeviceInfo> out;
  for (const auto& f : AllDevices())
    out.push_back(f.info);
  return out;
}

cl::Device ChooseOpenCLDevice(const std::string& choice, OpenCLDeviceInfo* info) {
  const auto all = AllDevices();
  if (all.empty())
    throw std::runtime_error("no OpenCL platform or device found");
  const Found* pick = nullptr;
  if (choice.empty()) {
    for (const auto& f : all)
      if (f.info.fp64 && f.info.type == "gpu") {
        pick = &f;
        break;
      }
    if (!pick)
      for (const auto& f : all)
        if (f.info.fp64) {
          pick = &f;
          break;
        }
    if (!pick)
      pick = &all.front();
  } else if (choice.find_first_not_of("0123456789") == std::string::npos) {
    const size_t k = std::stoul(choice);
    if (k >= all.size())
      throw std::runtime_error("OpenCL device " + choice + " does not exist (" +
                               std::to_string(all.size()) + " devices; see bmsim devices)");
    pick = &all[k];
  } else {
    for (const auto& f : all)
      if (f.info.name.find(choice) != std::string::npos) {
        pick = &f;
        break;
      }
    if (!pick)
      throw std::runtime_error("no OpenCL device name contains '" + choice + "'");
  }
  if (!pick->info.fp64)
    throw std::runtime_error("OpenCL device '" + pick->info.name +
                             "' lacks double precision (cl_khr_fp64), which the backend needs to "
                             "match the CPU backend exactly");
  if (info)
    *info = pick->info;
  return pick->device;
}

cl::Program BuildOpenCLProgram(const cl::Context& context, const cl::Device& device,
                               const char* source, const std::string& options) {
  cl::Program::Sources sources{std::string(kernels::bmCommon), std::string(source)};
  cl::Program program(context, sources);
  std::string all = "-cl-std=CL1.2 " + options;
  if (const char* extra = std::getenv("BM_OPENCL_BUILD_OPTIONS"); extra && *extra)
    all += std::string(" ") + extra;
  try {
    program.build({device}, all.c_str());
  } catch (const cl::Error&) {
    throw std::runtime_error("OpenCL kernel build failed:\n" +
                             program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device));
  }
  return program;
}

std::string DescribeOpenCLError(const cl::Error& e) {
  return std::string(e.what()) + " (OpenCL error " + std::to_string(e.err()) + ")";
}

} // namespace bm
