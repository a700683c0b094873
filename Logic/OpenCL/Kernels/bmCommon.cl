// bmCommon.cl - what every BoneMachining kernel program starts with (prepended by the host):
// double precision, optional 64-bit atomics, no FMA contraction (the CPU engines are compiled
// without it, and identical results need identical rounding), Morton decoding, the element's voxel
// and removal request, the residency rule and the work-group and removal sums.
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

// Frame flags (both frame kernels): material is removed this frame; cutting forces this frame;
// the voxmap has a material scale; every element removes, not only cutting ones
// (FrameInput::envelopeRemoves).
#define BM_FLAG_REMOVE 1
#define BM_FLAG_CUTTING 2
#define BM_FLAG_MATERIAL 4
#define BM_FLAG_ENVELOPE 8

// Voxel of the element with Morton code `code` (bit 0: cutting; then x, y, z interleaved): the
// float affine map A of bmFrameGeometry.h, rounded to the nearest voxel, (vi, vj, vk) in *v;
// returns its index (row and slice pitch `pitch`, bmVoxmap.h), or -1 outside the voxmap.
inline long ElementVoxel(ulong code, float4 A0, float4 A1, float4 A2, int4 dims, int2 pitch,
                         int* v) {
  const float x = (float)MortonCompact(code >> 1), y = (float)MortonCompact(code >> 2),
              z = (float)MortonCompact(code >> 3);
  const float gx = A0.x * x + A0.y * y + A0.z * z + A0.w;
  const float gy = A1.x * x + A1.y * y + A1.z * z + A1.w;
  const float gz = A2.x * x + A2.y * y + A2.z * z + A2.w;
  v[0] = (int)floor(gx + 0.5f);
  v[1] = (int)floor(gy + 0.5f);
  v[2] = (int)floor(gz + 0.5f);
  if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] >= dims.x || v[1] >= dims.y || v[2] >= dims.z)
    return -1;
  return v[0] + (long)pitch.x * (v[1] + (long)pitch.y * v[2]);
}

// Fill units engaged element e asks to remove this frame (FrameGeometry::RemovalUnits): what its
// area-normal sweeps along the motion (dx, dy, dz) mm, at most maxUnits; 0 when it faces away,
// when nothing is removed this frame, or when it does not cut and only cutting elements remove.
inline int RemovalUnits(__global const float* areaNormals, uint e, ulong code, int flags, double dx,
                        double dy, double dz, double unitsPerMm3, double maxUnits) {
  if (!(flags & BM_FLAG_REMOVE) || !((flags & BM_FLAG_ENVELOPE) || (code & 1)))
    return 0;
  const double vol =
      areaNormals[3 * e] * dx + areaNormals[3 * e + 1] * dy + areaNormals[3 * e + 2] * dz;
  if (!(vol > 0))
    return 0;
  const double want = vol * unitsPerMm3;
  return (int)((maxUnits < want ? maxUnits : want) + 0.5);
}

// Writes a removal kernel's sums (removedFill, removedVoxels) of this work item: atomically into
// out, or as its own partial in partials for the host to add.
inline void RemovalSumsOut(const long* R, __global long* partials, __global long* out) {
#ifdef BM_INT64_ATOMICS
  atom_add(out, R[0]);
  atom_add(out + 1, R[1]);
#else
  partials[get_global_id(0) * BM_REMOVAL_SUMS] = R[0];
  partials[get_global_id(0) * BM_REMOVAL_SUMS + 1] = R[1];
#endif
}

// ElementResidency::Stays: a visit in frameNo to voxel idx continues an engaged stay there, so
// the element cuts whatever the voxel's fill (the fill need not be read).
inline bool Stays(__global const Residency* st, uint frameNo, long idx) {
  return st->frame + 1 == frameNo && st->voxel == idx && st->engaged;
}

// ElementResidency::Visit: updates the state for a visit in frameNo to voxel idx (-1: outside)
// whose fill at the frame's start was `fill` (any value when Stays()); returns whether it cuts.
inline bool Visit(__global Residency* st, uint frameNo, long idx, int fill) {
  const bool stayed = Stays(st, frameNo, idx);
  const bool e = idx >= 0 && (fill > 0 || stayed);
  st->voxel = idx;
  st->frame = frameNo;
  st->engaged = e ? 1u : 0u;
  return e;
}

// Sums `n` quantities over the work-group: lane 0 adds them atomically into out, or writes them
// as the group's partial in partials for the host to add.
inline void GroupSum(long* mine, int n, __local long* scratch, __global long* partials,
                     __global long* out) {
  const uint L = get_local_size(0), l = get_local_id(0);
  if (L == 1) {
#ifdef BM_INT64_ATOMICS
    for (int q = 0; q < n; ++q)
      atom_add(out + q, mine[q]);
#else
    for (int q = 0; q < n; ++q)
      partials[get_group_id(0) * n + q] = mine[q];
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
      partials[get_group_id(0) * n + q] = scratch[q];
#endif
  }
}
