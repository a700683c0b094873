#include "bmGuideContact.h"

#include <algorithm>
#include <cmath>

namespace bm {

GuideContact::GuideContact(const ToolModel& tool, const Voxmap& bone) : Bone_(bone) {
  const auto* reamer = dynamic_cast<const ArcLipTool*>(&tool);
  if (!reamer || reamer->Params().nippleRadius <= 0 || reamer->Params().nippleLength <= 0)
    return;
  Radius_ = reamer->Params().nippleRadius;
  Length_ = reamer->Params().nippleLength;
  const double h = bone.Spacing();
  const double r = Radius_ - h; // one voxel inside the guide's rim
  const double z = -Length_;
  Samples_.emplace_back(0, 0, z);
  if (r <= 0)
    return;
  const int rings = std::max(1, int(std::ceil(r / (0.5 * h))));
  for (int i = 1; i <= rings; ++i) {
    const double ri = r * double(i) / rings;
    const int n = std::max(6, int(std::ceil(2 * 3.14159265358979323846 * ri / (0.5 * h))));
    for (int k = 0; k < n; ++k) {
      const double a = 2 * 3.14159265358979323846 * double(k) / n;
      Samples_.emplace_back(ri * std::cos(a), ri * std::sin(a), z);
    }
  }
}

double GuideContact::MaxFill(const FrameInput& pose) const {
  double fill = 0;
  std::array<int, 3> ijk{};
  for (const Eigen::Vector3d& s : Samples_) {
    const Eigen::Vector3d w = pose.rotation * s + pose.position;
    if (Bone_.VoxelAt({w(0), w(1), w(2)}, ijk))
      fill = std::max(fill, Bone_.Fraction(Bone_.Index(ijk[0], ijk[1], ijk[2])));
  }
  return fill;
}

} // namespace bm
