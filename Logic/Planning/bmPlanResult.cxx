// bmPlanResult.cxx - see bmPlanResult.h.
#include "bmPlanResult.h"

#include "bmAtomicFile.h"
#include "bmPlanRunReport.h"
#include "bmReamingOutcome.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

#include <filesystem>
#include <stdexcept>

namespace bm {
namespace {

double PlanValue(const nlohmann::json& plan, const char* key, double def) {
  return plan.is_object() && plan.contains(key) && plan.at(key).is_number()
             ? plan.at(key).get<double>()
             : def;
}

Vec3 PlanVec(const nlohmann::json& plan, const char* key, const Vec3& def) {
  if (!plan.is_object() || !plan.contains(key))
    return def;
  const nlohmann::json& j = plan.at(key);
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  return def;
}

} // namespace

nlohmann::json PlanResultSummary(const PlanResultInput& in) {
  if (!in.before || !in.after)
    throw std::invalid_argument("the plan's result needs the bone before and after its steps");
  if (in.before->Dims() != in.after->Dims() || in.before->Spacing() != in.after->Spacing() ||
      in.before->Origin() != in.after->Origin())
    throw std::invalid_argument("the bone before and after the plan's steps are not on one grid "
                                "(a bone from another session?)");
  nlohmann::json summary = {
      {"plan", in.planName}, {"steps", in.steps}, {"completed", in.completed}};
  if (!in.planning.is_null())
    summary["planning"] = in.planning;
  if (in.reamer) {
    ReamingOutcomeOptions o;
    const nlohmann::json& p = in.planning;
    o.baseplateDiameterMm = PlanValue(p, "baseplate_diameter_mm", o.baseplateDiameterMm);
    o.backRadiusMm = PlanValue(p, "baseplate_back_radius_mm", o.backRadiusMm);
    o.gapMm = PlanValue(p, "seating_gap_mm", o.gapMm);
    o.pegLengthMm = PlanValue(p, "peg_length_mm", o.pegLengthMm);
    o.pegRadiusMm = PlanValue(p, "peg_radius_mm", o.pegRadiusMm);
    o.pinRadiusMm = PlanValue(p, "pin_radius_mm", o.pinRadiusMm);
    o.pinDepthMm = PlanValue(p, "pin_depth_mm", o.pinDepthMm);
    const Vec3 entry = PlanVec(p, "entry_mm", in.trialEntry);
    const Vec3 axis = Normalized(PlanVec(p, "axis", in.trialAxis));
    const ReamingOutcome outcome =
        MeasureReamingOutcome(*in.before, *in.after, entry, axis, *in.reamer, in.reamReachedMm, o);
    summary["outcome"] = outcome.ToJson();
    summary["outcome"]["options"] = {{"baseplate_diameter_mm", o.baseplateDiameterMm},
                                     {"baseplate_back_radius_mm", o.backRadiusMm},
                                     {"seating_gap_mm", o.gapMm},
                                     {"peg_length_mm", o.pegLengthMm},
                                     {"peg_radius_mm", o.pegRadiusMm}};
  }
  return WithFaceAngles(std::move(summary));
}

nlohmann::json WritePlanResult(const std::string& dir, const PlanResultInput& in,
                               const PlanPictureWriter& pictures) {
  namespace fs = std::filesystem;
  nlohmann::json summary = PlanResultSummary(in);
  fs::create_directories(dir);
  if (pictures && in.planning.is_object() && in.planning.contains("entry_mm") &&
      in.planning.contains("axis")) {
    const auto [before, after] = pictures(dir, *in.before, *in.after, in.planning);
    summary["pictures"] = {{"before", before}, {"after", after}};
  }
  // The summary last among the set: it says the set is complete.
  WriteFilesAtomic({{(fs::path(dir) / "plan_result.md").string(), PlanRunMarkdown(summary)},
                    {(fs::path(dir) / "plan_result.html").string(), PlanRunHtml(summary)},
                    {(fs::path(dir) / "summary.json").string(), summary.dump(2) + "\n"}});
  return summary;
}

} // namespace bm
