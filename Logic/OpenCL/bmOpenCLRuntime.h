// bmOpenCLRuntime.h - one OpenCL device in use by an engine: context, in-order queue and the way
// work is split on it.
//
// Work split (OpenCLOptions, 0 / -1 = automatic):
//  - lanes: work-items per work-group. CPU devices (PoCL): 1, because work-group barriers and
//    per-item atomics are slow there (Docs/Platform.md section 4); GPUs: 128.
//  - groups: most work-groups per launch, each looping over blocks g, g + groups, ... CPU devices:
//    4 per compute unit; GPUs: 1024 (on an H100, shell 2048^3 x voxmap 1024^3: frame p99 0.069 ms
//    at 1024 groups of 128, 0.090 at 4096, 0.174 at 16384; 64 and 32 lanes at 4096 groups 0.079
//    and 0.080, 256 lanes 0.133; Docs/Performance.md).
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
  std::string device; ///< ChooseOpenCLDevice's choice ("" = first GPU, else first device)
  /// Work-items per group, power of two; 0 = automatic ($BM_OPENCL_LANES when set).
  int lanes = 0;
  /// Most work-groups per launch; 0 = automatic ($BM_OPENCL_GROUPS when set).
  int groups = 0;
  int int64Atomics = -1; ///< 1 on, 0 off, -1 automatic
  /// The cut is held on the device alone and the caller's Voxmap brought up to date only by
  /// SyncBone() (default false: the Voxmap is kept current after every frame; bmOpenCLEngine.h).
  bool deviceHeldBone = false;
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
  bool deviceHeldBone = false; ///< OpenCLOptions::deviceHeldBone
  /// Build options for the kernel programs ("-DBM_INT64_ATOMICS" when used, "-DBM_HOST_MIRROR"
  /// unless the bone is held on the device).
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
