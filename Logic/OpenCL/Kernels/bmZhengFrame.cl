// bmZhengFrame.cl - the baseline of bmZhengEngine.cxx (Zheng et al.) as OpenCL C 1.2 kernels.
//
// Same arithmetic, order and precision as the CPU baseline, so results are identical: every
// element (no block culling) walks the octree from the root to its voxel's leaf, evaluates its
// elemental force from the per-bin model terms (k = a + b / V, mu = 0 on the lips, as
// ForceModel::Evaluate with the voxel's material) and writes it to a per-element buffer; a
// separate reduction kernel sums the buffer in chunks of BM_ZHENG_CHUNK elements (the CPU
// baseline's chunking; the host adds the chunk sums in order). Leaves that a removal request
// falls in but that cover more than one voxel are listed for the host, which splits them (as
// OctreeVoxmap::Refine) and uploads the new nodes before the removal kernel runs.
//
// Octree nodes: int2 (child index of the first of 8 children or -1 for a leaf, leaf fill).

#define BM_ZHENG_SUMS 4 // visited, engaged, engagedCutting, requested
#define BM_ZHENG_CHUNK 4096
#define BM_ZHENG_TERMS 10 // per force bin: kc, kt, au, dirN xyz, dirT xyz, r

inline int FindLeaf(__global const int2* nodes, int levels, int i, int j, int k, int* level) {
  int node = 0;
  int lv = levels;
  while (nodes[node].x >= 0) {
    --lv;
    const int c = ((i >> lv) & 1) | (((j >> lv) & 1) << 1) | (((k >> lv) & 1) << 2);
    node = nodes[node].x + c;
  }
  *level = lv;
  return node;
}

// Work item t takes elements [t * per, (t + 1) * per). Refinement requests: (i, j, k) of voxels
// whose leaf is coarser than a voxel (one atomic counter increment each; only where the cut
// reaches new octree cells).
__kernel void zheng_collide(const uint n, const uint per, __global const ulong* codes,
                            __global const float* areaNormals, __global const ushort* bins,
                            __global const float* deltas, __global const double2* radial,
                            __global const double* terms, __global const int2* nodes,
                            const int levels, __global const float* material,
                            __global Residency* state, __global int* units,
                            __global double4* buffer, __global long* sums, __local long* scratch,
                            __global uint* refineCount, __global int4* refine, const float4 A0,
                            const float4 A1, const float4 A2, const int4 dims, const int2 pitch,
                            const uint frameNo,
                            const int flags, const double dx, const double dy, const double dz,
                            const double unitsPerMm3, const double maxUnits) {
  const bool cutting = flags & BM_FLAG_CUTTING, hasMaterial = flags & BM_FLAG_MATERIAL;
  long P[BM_ZHENG_SUMS] = {0, 0, 0, 0};
  const uint begin = get_global_id(0) * per;
  const uint end = min(n, begin + per);
  for (uint e = begin; e < end; ++e) {
    buffer[e] = (double4)(0.0, 0.0, 0.0, 0.0);
    units[e] = 0;
    const ulong code = codes[e];
    int v[3];
    const long idx = ElementVoxel(code, A0, A1, A2, dims, pitch, v);
    ++P[0];
    __global Residency* st = state + e;
    if (idx < 0) {
      Visit(st, frameNo, -1, 0);
      continue;
    }
    int level = 0;
    const int leaf = FindLeaf(nodes, levels, v[0], v[1], v[2], &level);
    if (!Visit(st, frameNo, idx, nodes[leaf].y))
      continue;
    ++P[1];
    const int u = RemovalUnits(areaNormals, e, code, flags, dx, dy, dz, unitsPerMm3, maxUnits);
    if (u > 0) {
      units[e] = u;
      P[3] += u;
      if (level > 0)
        refine[atomic_inc(refineCount)] = (int4)(v[0], v[1], v[2], 0);
    }
    if (cutting && (code & 1)) {
      ++P[2];
      __global const double* t = terms + BM_ZHENG_TERMS * bins[e];
      const double mat = hasMaterial ? (double)material[idx] : 1.0;
      const double s = mat * t[2];
      const double fx = s * (t[0] * t[3] + t[1] * t[6]);
      const double fy = s * (t[0] * t[4] + t[1] * t[7]);
      const double fz = s * (t[0] * t[5] + t[1] * t[8]);
      const double w = (double)deltas[e];
      const double c = radial[e].x, sn = radial[e].y; // PointShell::RadialDirs()
      buffer[e] = (double4)(w * (fx * c - fy * sn), w * (fx * sn + fy * c), w * fz, -w * t[9] * fy);
    }
  }
  GroupSum(P, BM_ZHENG_SUMS, scratch, sums, sums);
}

// The reduction pass: work item c sums chunk c of the buffer in element order.
__kernel void zheng_reduce(const uint n, __global const double4* buffer,
                           __global double4* chunkSums) {
  const uint c = get_global_id(0);
  const uint begin = c * BM_ZHENG_CHUNK;
  const uint end = min(n, begin + BM_ZHENG_CHUNK);
  double4 s = (double4)(0.0, 0.0, 0.0, 0.0);
  for (uint e = begin; e < end; ++e)
    s += buffer[e];
  chunkSums[c] = s;
}

// Removal after the host refined the leaves: work item t walks its element range in order and
// merges the requests of one voxel into one atomic subtraction on the voxel's leaf.
inline void ZhengFlush(__global int2* nodes, int levels, int2 pitch, long idx, int amount,
                       long* R) {
  const int i = (int)(idx % pitch.x);
  const long rest = idx / pitch.x;
  const int j = (int)(rest % pitch.y), k = (int)(rest / pitch.y);
  int level = 0;
  const int leaf = FindLeaf(nodes, levels, i, j, k, &level);
  const int old = atomic_sub((__global int*)nodes + 2 * leaf + 1, amount);
  const int after = old - amount;
  R[0] += max(old, 0) - max(after, 0);
  if (old > 0 && after <= 0)
    ++R[1];
}

__kernel void zheng_remove(const uint n, const uint per, __global const Residency* state,
                           __global const int* units, __global int2* nodes, const int levels,
                           const int2 pitch, __global long* sums) {
  long R[BM_REMOVAL_SUMS] = {0, 0};
  const uint begin = get_global_id(0) * per;
  const uint end = min(n, begin + per);
  long cur = -1;
  int amount = 0;
  for (uint e = begin; e < end; ++e) {
    const int u = units[e];
    if (u <= 0)
      continue;
    const long idx = state[e].voxel;
    if (idx != cur || amount > BM_MERGE_LIMIT - u) {
      if (amount > 0)
        ZhengFlush(nodes, levels, pitch, cur, amount, R);
      cur = idx;
      amount = 0;
    }
    amount += u;
  }
  if (amount > 0)
    ZhengFlush(nodes, levels, pitch, cur, amount, R);
  RemovalSumsOut(R, sums, sums);
}
