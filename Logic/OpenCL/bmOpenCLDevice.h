// bmOpenCLDevice.h - the OpenCL devices of this machine, choosing one, and building the kernels.
//
// Devices are numbered across all platforms in the order the ICD loader reports them (the
// numbers `bmsim devices` prints). A device is usable when it runs OpenCL C 1.2 with double
// precision (cl_khr_fp64): elemental forces are computed in double so that the OpenCL backend
// gives exactly the CPU backend's results.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <CL/opencl.hpp>

namespace bm {

struct OpenCLDeviceInfo {
  int index = 0;        ///< number across platforms
  std::string platform; ///< platform name
  std::string name;     ///< device name
  std::string type;     ///< "gpu", "cpu", "accelerator" or "other"
  std::string version;  ///< CL_DEVICE_VERSION
  int computeUnits = 0;
  size_t globalMemoryBytes = 0;
  bool fp64 = false;         ///< cl_khr_fp64 (required)
  bool int64Atomics = false; ///< cl_khr_int64_base_atomics (used on GPUs when present)
};

/// Every OpenCL device; empty when there is no platform (no ICD installed or no driver).
std::vector<OpenCLDeviceInfo> ListOpenCLDevices();

/// The device for `choice`: "" = the first usable GPU, else the first usable device; a number =
/// that index; otherwise the first device whose name contains `choice` (case-sensitive).
/// Throws std::runtime_error naming the reason (no platform, no match, no fp64).
cl::Device ChooseOpenCLDevice(const std::string& choice, OpenCLDeviceInfo* info = nullptr);

/// Builds bmCommon.cl followed by `source` for `device` with `options` (e.g. "-DBM_INT64_ATOMICS"),
/// then $BM_OPENCL_BUILD_OPTIONS when set (a diagnosis of a device's compiler, e.g.
/// "-cl-opt-disable"). Throws std::runtime_error with the build log on failure.
cl::Program BuildOpenCLProgram(const cl::Context& context, const cl::Device& device,
                               const char* source, const std::string& options);

/// "message (OpenCL error N)" for an OpenCL C++ exception.
std::string DescribeOpenCLError(const cl::Error& e);

} // namespace bm
