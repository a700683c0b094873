// bmVpsFrame.cl - the VPS frame of bmCpuEngine.cxx (Faieghi et al.) as OpenCL C 1.2 kernels.
//
// Every operation repeats the CPU engine's arithmetic in the same order and precision, so the
// results are identical: the block culling of bmCpuEngine.cxx BlockVisible (in double, as
// FrameGeometry::VoxelBox and Voxmap::AnyBoneIn), the float transform of the element grid into
// the voxmap (no FMA contraction), the residency rule of bmElementResidency.h, removal units and
// elemental forces in double, fixed-point int64 sums (order-independent).
//
// Work split: work-group g takes blocks g, g + G, g + 2G, ... of the whole shell; its lanes cull
// the block and take its elements begin + l, begin + l + L, ... when it is visible (L = local
// size). On a CPU device (PoCL) L = 1 and G is a few groups per core; on a
// GPU L = 128 and G is large. Nothing is decided on the host but the frame's geometry: a frame
// is one launch of each kernel and one read of the frame's sums.
//
// Sums leave a group either as one partial per group (read back and summed on the host in int64)
// or, with BM_INT64_ATOMICS, as one 64-bit atomic add per group and quantity into the frame's half
// of the meta buffer. The meta buffer holds two halves of BM_META longs; a frame uses half h and
// the collision kernel's first work item clears half 1 - h for the next frame (the host read it
// in the frame before), so no buffer is filled between frames. Half layout: [0, 8) the collision
// sums (atomic mode), [8] the removal log's length (uint in the low word), [9, 11) the removal
// sums (atomic mode).

#define BM_META 16
#define BM_META_LOG 8
#define BM_META_REMOVAL 9

// Per block of the shell: 12 floats (lo xyz, hi xyz of the elements' voxels, nLo xyz, nHi xyz of
// their unit normals; PointShell ShellBlock) and (begin, end, hasCutting, 0).

// Voxmap::AnyBoneIn on the device's brick counts (voxel box inclusive, clamped to the grid).
inline bool AnyBoneIn(__global const int* bricks, int lo0, int lo1, int lo2, int hi0, int hi1,
                      int hi2, int4 dims, int4 brickDims) {
  lo0 = max(lo0, 0);
  lo1 = max(lo1, 0);
  lo2 = max(lo2, 0);
  hi0 = min(hi0, dims.x - 1);
  hi1 = min(hi1, dims.y - 1);
  hi2 = min(hi2, dims.z - 1);
  if (lo0 > hi0 || lo1 > hi1 || lo2 > hi2)
    return false;
  for (int bk = lo2 / 8; bk <= hi2 / 8; ++bk)
    for (int bj = lo1 / 8; bj <= hi1 / 8; ++bj)
      for (int bi = lo0 / 8; bi <= hi0 / 8; ++bi)
        if (bricks[bi + (long)brickDims.x * (bj + (long)brickDims.y * bk)] > 0)
          return true;
  return false;
}

// BlockVisible (bmCpuEngine.cxx) with the engine's culling (motion and blocks): a block without
// cutting elements counts only while some normal faces the motion d and material is removed;
// then its voxel box (FrameGeometry::VoxelBox: the 8 corners of its box, world = R p + position,
// grid = (world - origin) / h, rounded to the nearest voxel) must hold bone.
inline bool BlockVisible(__global const float* box, uint hasCutting, __global const int* bricks,
                         const double* R, const double* pos, const double* org, double h, double dx,
                         double dy, double dz, int flags, int4 dims, int4 brickDims) {
  if (!hasCutting) {
    double up = 0;
    const double d[3] = {dx, dy, dz};
    for (int a = 0; a < 3; ++a) {
      const double l = (double)box[6 + a] * d[a], u = (double)box[9 + a] * d[a];
      up += l < u ? u : l;
    }
    if (up <= 0 || !(flags & BM_FLAG_REMOVE))
      return false;
  }
  int lo[3] = {INT_MAX, INT_MAX, INT_MAX}, hi[3] = {INT_MIN, INT_MIN, INT_MIN};
  for (int c = 0; c < 8; ++c) {
    const double p0 = (double)((c & 1) ? box[3] : box[0]);
    const double p1 = (double)((c & 2) ? box[4] : box[1]);
    const double p2 = (double)((c & 4) ? box[5] : box[2]);
    for (int a = 0; a < 3; ++a) {
      const double w = R[3 * a] * p0 + R[3 * a + 1] * p1 + R[3 * a + 2] * p2;
      const double g = (w + pos[a] - org[a]) / h;
      const int v = (int)floor(g + 0.5);
      lo[a] = min(lo[a], v);
      hi[a] = max(hi[a], v);
    }
  }
  return AnyBoneIn(bricks, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], dims, brickDims);
}

// Phase 1: culling, collision, residency, removal requests (units per element, 0 for none) and
// forces, all against the fills at the frame's start. A rows: A0, A1, A2 (xyz) with b in w.
// G0-G3, for the culling: the rotation tool -> world row-major (G0.xyzw, G1.xyzw, G2.x), the
// tool's position (G2.yzw, world mm), the voxmap's origin (G3.xyz, world mm of voxel (0,0,0)'s
// centre) and voxel size (G3.w, mm). Visible blocks are marked with the frame number in
// visibleFrame for the removal kernel. flags: BM_FLAG_* (bmCommon.cl).
__kernel void vps_collide(
    const uint nBlocks, __global const float* blockBox, __global const uint4* blockInfo,
    __global const int* bricks, __global uint* visibleFrame, __global const ulong* codes,
    __global const float* areaNormals, __global const ushort* bins, __global const float* deltas,
    __global const double* table, __global const double2* radial, __global const int* fill,
    __global const float* material, __global Residency* state, __global int* units,
    __global long* partials, __global long* meta, const uint metaHalf, __local long* scratch,
    const float4 A0, const float4 A1, const float4 A2, const int4 dims, const int2 pitch,
    const int4 brickDims, const double4 G0, const double4 G1, const double4 G2, const double4 G3,
    const uint frameNo, const int flags, const double dx, const double dy, const double dz,
    const double unitsPerMm3, const double maxUnits, const double scale) {
  const uint G = get_num_groups(0), L = get_local_size(0), l = get_local_id(0);
  if (get_global_id(0) == 0)
    for (int q = 0; q < BM_META; ++q)
      meta[(1 - metaHalf) * BM_META + q] = 0;
  const bool cutting = flags & BM_FLAG_CUTTING, hasMaterial = flags & BM_FLAG_MATERIAL;
  long P[BM_SUMS] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (uint b = get_group_id(0); b < nBlocks; b += G) {
    const uint4 info = blockInfo[b];
    // Every lane culls the block (the same arithmetic on the same data, so the same answer; on
    // a GPU the lanes run it side by side in the time one would take, and no barrier is needed).
    const double R[9] = {G0.x, G0.y, G0.z, G0.w, G1.x, G1.y, G1.z, G1.w, G2.x};
    const double pos[3] = {G2.y, G2.z, G2.w}, org[3] = {G3.x, G3.y, G3.z};
    if (!BlockVisible(blockBox + 12 * b, info.z, bricks, R, pos, org, G3.w, dx, dy, dz, flags, dims,
                      brickDims))
      continue;
    if (l == 0)
      visibleFrame[b] = frameNo;
    for (uint e = info.x + l; e < info.y; e += L) {
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
  GroupSum(P, BM_SUMS, scratch, partials, meta + metaHalf * BM_META);
}

// Phase 2: removal, after every collision read of the frame. Work-group g takes the visible
// blocks g, g + G, ...; lane l of L walks its run of about n / L consecutive elements of the block
// in element order and merges the requests of one voxel into one atomic subtraction (exact: the
// removed fill and the voided count of a voxel depend only on its total request, whatever the
// runs). On a CPU device (L = 1) one work item walks the whole block. A voxel taken to void leaves
// its brick's count (the culling's occupancy, kept on the device). With BM_HOST_MIRROR every
// merged request is logged as (voxel, units) for the host, which applies the same requests to its
// Voxmap (Voxmap::RemoveOwned: the same fills, the same totals); the log has room for one entry
// per element, the most a frame can make.
inline void Flush(__global int* fill, __global int* bricks, long idx, int amount, long* R,
                  int2 pitch, int4 brickDims, __global long* removalLog, __global uint* logLength) {
  const int old = atomic_sub(fill + idx, amount);
  const int after = old - amount;
  R[0] += max(old, 0) - max(after, 0);
  if (old > 0 && after <= 0) {
    ++R[1];
    const long rest = idx / pitch.x;
    const int i = (int)(idx - rest * pitch.x), j = (int)(rest % pitch.y), k = (int)(rest / pitch.y);
    atomic_dec(bricks + (i >> 3) + (long)brickDims.x * ((j >> 3) + (long)brickDims.y * (k >> 3)));
  }
#ifdef BM_HOST_MIRROR
  const uint at = atomic_inc(logLength);
  removalLog[2 * at] = idx;
  removalLog[2 * at + 1] = amount;
#endif
}

__kernel void vps_remove(const uint nBlocks, __global const uint4* blockInfo,
                         __global const uint* visibleFrame, const uint frameNo,
                         __global const Residency* state, __global const int* units,
                         __global int* fill, __global int* bricks, const int2 pitch,
                         const int4 brickDims, __global long* partials, __global long* meta,
                         const uint metaHalf, __global long* removalLog, __local long* scratch) {
  const uint G = get_num_groups(0), L = get_local_size(0), l = get_local_id(0);
  __global long* m = meta + metaHalf * BM_META;
  __global uint* logLength = (__global uint*)(m + BM_META_LOG);
  long R[BM_REMOVAL_SUMS] = {0, 0};
  for (uint b = get_group_id(0); b < nBlocks; b += G) {
    if (visibleFrame[b] != frameNo)
      continue;
    const uint4 info = blockInfo[b];
    const uint n = info.y - info.x, per = (n + L - 1) / L;
    const uint e0 = info.x + min(n, l * per), e1 = info.x + min(n, (l + 1) * per);
    long cur = -1;
    int amount = 0;
    for (uint e = e0; e < e1; ++e) {
      const int u = units[e];
      if (u <= 0)
        continue;
      const long idx = state[e].voxel;
      if (idx != cur || amount > BM_MERGE_LIMIT - u) {
        if (amount > 0)
          Flush(fill, bricks, cur, amount, R, pitch, brickDims, removalLog, logLength);
        cur = idx;
        amount = 0;
      }
      amount += u;
    }
    if (amount > 0)
      Flush(fill, bricks, cur, amount, R, pitch, brickDims, removalLog, logLength);
  }
  GroupSum(R, BM_REMOVAL_SUMS, scratch, partials, m + BM_META_REMOVAL);
}
