// bmMemoryBudget.h - how much memory a large allocation (a CT, a voxmap) may take: a request is
// refused with a message before it is allocated, rather than killed by the kernel or failing in
// std::bad_alloc. The default budget follows the memory this process may really use: in a
// container with a 2 GiB control-group limit, planning for the host's RAM gets the process killed
// without a word.
#pragma once

#include <cstdint>
#include <string>

namespace bm {

/// Default memory budget, bytes: 75 % of the memory this process may use, the smaller of the
/// machine's physical memory and its control group's limit (CgroupMemoryLimit): in a 2 GiB
/// container the kernel kills a process that plans for the host's RAM, without a message.
uint64_t DefaultMemoryLimit();

/// The memory limit (bytes) of this process's control group, cgroup v2 (memory.max) or v1
/// (memory.limit_in_bytes), at the hierarchy's root and at the process's own group as
/// `selfCgroup` (/proc/self/cgroup) names it under `root`; the smallest one set, 0 when none is.
uint64_t CgroupMemoryLimit(const std::string& root = "/sys/fs/cgroup",
                           const std::string& selfCgroup = "/proc/self/cgroup");

/// Throw std::runtime_error "<what> needs N MiB ..., more than the M MiB allowed" when bytes
/// exceeds limitBytes (0 = DefaultMemoryLimit()). Called before any large allocation.
void CheckMemoryBudget(uint64_t bytes, uint64_t limitBytes, const std::string& what);
} // namespace bm
