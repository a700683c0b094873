// bmCommon.cl - what every BoneMachining kernel program starts with (prepended by the host):
// double precision, optional 64-bit atomics, no FMA contraction (the CPU engines are compiled
// without it, and identical results need identical rounding), Morton decoding, the residency rule
// and the work-group sum.
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#ifdef BM_INT64_ATOMICS
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#endif
#pragma OPENCL FP_CONTRACT OFF

#define BM_SUMS 8         // thrust, torque, fx, fy, visited, engaged, engagedCutting, requested
#define BM_REMOVAL_SUMS 2 // removedFill, removedVoxels
// Largest merged removal of one voxel in one atomic subtraction (no int32 overflow).
#define BM_MERGE_LIMIT (1 << 30)

// Per-element residency (bmElementResidency.h): 16 bytes, the host struct's layout.
typedef struct {
  long voxel;
  uint frame;
  uint engaged;
} Residency;

inline uint MortonCompact(ulong x) {
  x &= 0x1249249249249249UL;
  x = (x ^ (x >> 2)) & 0x10c30c30c30c30c3UL;
  x = (x ^ (x >> 4)) & 0x100f00f00f00f00fUL;
  x = (x ^ (x >> 8)) & 0x1f0000ff0000ffUL;
  x = (x ^ (x >> 16)) & 0x1f00000000ffffUL;
  x = (x ^ (x >> 32)) & 0x1fffffUL;
  return (uint)x;
}

inline bool Visit(__global Residency* st, uint frameNo, long idx, int fill) {
  const bool stayed = st->frame + 1 == frameNo && st->voxel == idx && st->engaged;
  const bool e = idx >= 0 && (fill > 0 || stayed);
  st->voxel = idx;
  st->frame = frameNo;
  st->engaged = e ? 1u : 0u;
  return e;
}

// Sums `n` quantities over the work-group into out (lane 0 writes or adds them).
inline void GroupSum(long* mine, int n, __local long* scratch, __global long* out) {
  const uint L = get_local_size(0), l = get_local_id(0);
  if (L == 1) {
#ifdef BM_INT64_ATOMICS
    for (int q = 0; q < n; ++q)
      atom_add(out + q, mine[q]);
#else
    for (int q = 0; q < n; ++q)
      out[get_group_id(0) * n + q] = mine[q];
#endif
    return;
  }
  for (int q = 0; q < n; ++q)
    scratch[l * n + q] = mine[q];
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint s = L / 2; s > 0; s >>= 1) {
    if (l < s)
      for (int q = 0; q < n; ++q)
        scratch[l * n + q] += scratch[(l + s) * n + q];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) {
#ifdef BM_INT64_ATOMICS
    for (int q = 0; q < n; ++q)
      atom_add(out + q, scratch[q]);
#else
    for (int q = 0; q < n; ++q)
      out[get_group_id(0) * n + q] = scratch[q];
#endif
  }
}
