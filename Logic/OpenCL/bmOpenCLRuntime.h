// bmOpenCLRuntime.h - one OpenCL device in use by an engine: context, in-order queue and the way
// work is split on it.
//
// Work split (OpenCLOptions, 0 / -1 = automatic):
//  - lanes: work-items per work-group. CPU devices (PoCL): 1, because work-group barriers and
//    per-item atomics are slow there (Docs/Platform.md section 4); GPUs: 128.
//  - groups: most work-groups per launch. CPU devices: 4 per compute unit, each looping over many
//    blocks; GPUs: 4096.
//  - int64Atomics: sums leave each work-group as 64-bit atomic adds (cl_khr_int64_base_atomics)
//    instead of per-group partials summed on the host. Automatic: on GPUs that have it. Integer
//    sums are exact in any order, so both ways give the same totals.
#pragma once

#include <stdexcept>
#include <string>

#include "bmEngine.h"
#include "bmOpenCLDevice.h"

namespace bm {

struct OpenCLOptions {
  std::string device;    ///< ChooseOpenCLDevice's choice ("" = first GPU, else first device)
  int lanes = 0;         ///< work-items per group, power of two; 0 = automatic
  int groups = 0;        ///< most work-groups per launch; 0 = automatic
  int int64Atomics = -1; ///< 1 on, 0 off, -1 automatic
};

struct OpenCLRuntime {
  /// Chooses the device and resolves the automatic options. Throws std::runtime_error.
  explicit OpenCLRuntime(const OpenCLOptions& options);

  OpenCLDeviceInfo info;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;
  int lanes = 1;
  int groups = 8;
  bool int64Atomics = false;
  /// Build options for the kernel programs ("-DBM_INT64_ATOMICS" when used).
  std::string BuildOptions() const;
  /// "opencl(<device name>)".
  std::string Label() const { return "opencl(" + info.name + ")"; }

  /// Bytes the engine holds on the device: Upload adds to it, an engine growing a buffer too.
  size_t deviceBytes = 0;
  /// A device buffer of `bytes` (at least 8) with `flags` (default read-only for the kernels),
  /// filled from `data` when not null (blocking write). Throws cl::Error.
  cl::Buffer Upload(const void* data, size_t bytes, cl_mem_flags flags = CL_MEM_READ_ONLY);
  /// Runs an engine's set-up `build` (uploads, program, warm-up frame), turning an OpenCL error
  /// into std::runtime_error("OpenCL backend on '<device>': <error>").
  template <class F> void BuildEngine(F&& build) const {
    try {
      build();
    } catch (const cl::Error& e) {
      throw std::runtime_error("OpenCL backend on '" + info.name + "': " + DescribeOpenCLError(e));
    }
  }
  /// The constructors' warm-up frame: moving, far from any bone, so that every kernel is launched
  /// once (PoCL compiles a kernel at its first launch, 40-170 ms) while nothing engages.
  static FrameInput WarmUpFrame();
};

} // namespace bm
