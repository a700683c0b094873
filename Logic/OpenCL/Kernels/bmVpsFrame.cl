// bmVpsFrame.cl - the VPS frame of bmCpuEngine.cxx (Faieghi et al.) as OpenCL C 1.2 kernels.
//
// Every operation repeats the CPU engine's arithmetic in the same order and precision, so the
// results are identical: the float transform of the element grid into the voxmap (no FMA
// contraction), the residency rule of bmElementResidency.h, removal units and elemental forces in
// double, fixed-point int64 sums (order-independent). The host culls blocks exactly as the CPU
// engine does and passes the visible blocks.
//
// Work split (both kernels): work-group g takes visible blocks g, g + G, g + 2G, ...; inside a
// block lane l takes elements begin + l, begin + l + L, ... (L = local size). On a CPU device
// (PoCL) L = 1 and G is a few groups per core; on a GPU L = 128 and G is large.
// Sums leave a group either as one partial per group (read back and summed on the host in int64)
// or, with BM_INT64_ATOMICS, as one 64-bit atomic add per group and quantity.

// Phase 1: collision, residency, removal requests (units per element, 0 for none) and forces,
// all against the fills at the frame's start. A rows: A0, A1, A2 (xyz) with b in w.
// flags: BM_FLAG_* (bmCommon.cl).
__kernel void vps_collide(__global const uint* visible, const uint nVisible,
                          __global const uint2* blockRange, __global const ulong* codes,
                          __global const float* areaNormals, __global const ushort* bins,
                          __global const float* deltas, __global const double* table,
                          __global const double2* radial, __global const int* fill,
                          __global const float* material, __global Residency* state,
                          __global int* units, __global long* sums, __local long* scratch,
                          const float4 A0, const float4 A1, const float4 A2, const int4 dims,
                          const int2 pitch, const uint frameNo, const int flags, const double dx,
                          const double dy, const double dz, const double unitsPerMm3,
                          const double maxUnits, const double scale) {
  const uint G = get_num_groups(0), L = get_local_size(0), l = get_local_id(0);
  const bool cutting = flags & BM_FLAG_CUTTING, hasMaterial = flags & BM_FLAG_MATERIAL;
  long P[BM_SUMS] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (uint v = get_group_id(0); v < nVisible; v += G) {
    const uint2 range = blockRange[visible[v]];
    for (uint e = range.x + l; e < range.y; e += L) {
      const ulong code = codes[e];
      int ijk[3];
      const long idx = ElementVoxel(code, A0, A1, A2, dims, pitch, ijk);
      ++P[4];
      units[e] = 0;
      // As the CPU engine: an element that stays engaged in its voxel reads no fill (most of
      // them in steady cutting, and each read is a random one into the whole voxmap).
      const int f = idx < 0 || Stays(state + e, frameNo, idx) ? 0 : fill[idx];
      if (!Visit(state + e, frameNo, idx, f))
        continue;
      ++P[5];
      const int u = RemovalUnits(areaNormals, e, code, flags, dx, dy, dz, unitsPerMm3, maxUnits);
      if (u > 0) {
        units[e] = u;
        P[7] += u;
      }
      if (cutting && (code & 1)) {
        ++P[6];
        const ushort bin = bins[e];
        const double w = (double)(deltas[e] * (hasMaterial ? material[idx] : 1.0f));
        // bmForceModel.h BinForce: fx, fy, fz, torque per mm of delta.
        const double t0 = table[4 * bin], t1 = table[4 * bin + 1], t2 = table[4 * bin + 2];
        const double tm = table[4 * bin + 3];
        const double c = radial[e].x, s = radial[e].y; // PointShell::RadialDirs()
        P[0] += (long)(w * t2 * scale);
        P[1] += (long)(w * tm * scale);
        P[2] += (long)(w * (t0 * c - t1 * s) * scale);
        P[3] += (long)(w * (t0 * s + t1 * c) * scale);
      }
    }
  }
  GroupSum(P, BM_SUMS, scratch, sums);
}

// Phase 2: removal, after every collision read of the frame. One work item walks whole blocks
// in element order and merges the requests of one voxel into one atomic subtraction (exact: the
// removed fill and the voided count of a voxel depend only on its total request). Voxels taken
// to void are listed (one atomic counter increment each, a few per frame).
inline void Flush(__global int* fill, long idx, int amount, long* R, __global uint* voidedCount,
                  __global long* voided) {
  const int old = atomic_sub(fill + idx, amount);
  const int after = old - amount;
  R[0] += max(old, 0) - max(after, 0);
  if (old > 0 && after <= 0) {
    ++R[1];
    voided[atomic_inc(voidedCount)] = idx;
  }
}

__kernel void vps_remove(__global const uint* visible, const uint nVisible,
                         __global const uint2* blockRange, __global const Residency* state,
                         __global const int* units, __global int* fill, __global long* sums,
                         __global uint* voidedCount, __global long* voided) {
  const uint T = get_global_size(0);
  long R[BM_REMOVAL_SUMS] = {0, 0};
  for (uint v = get_global_id(0); v < nVisible; v += T) {
    const uint2 range = blockRange[visible[v]];
    long cur = -1;
    int amount = 0;
    for (uint e = range.x; e < range.y; ++e) {
      const int u = units[e];
      if (u <= 0)
        continue;
      const long idx = state[e].voxel;
      if (idx != cur || amount > BM_MERGE_LIMIT - u) {
        if (amount > 0)
          Flush(fill, cur, amount, R, voidedCount, voided);
        cur = idx;
        amount = 0;
      }
      amount += u;
    }
    if (amount > 0)
      Flush(fill, cur, amount, R, voidedCount, voided);
  }
  RemovalSumsOut(R, sums);
}
