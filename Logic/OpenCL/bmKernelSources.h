// bmKernelSources.h - the OpenCL C 1.2 kernel files (Kernels/*.cl), embedded at build time.
#pragma once

namespace bm::kernels {

/// Kernels/bmCommon.cl: extensions, FP_CONTRACT OFF, Morton decoding, residency, group sums.
extern const char* const bmCommon;
/// Kernels/bmVpsFrame.cl: the VPS frame (vps_collide, vps_remove).
extern const char* const bmVpsFrame;
/// Kernels/bmZhengFrame.cl: the Zheng baseline (zheng_collide, zheng_reduce, zheng_remove).
extern const char* const bmZhengFrame;

} // namespace bm::kernels
