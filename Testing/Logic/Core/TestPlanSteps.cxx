// A plan's steps (bmScene.h SceneStep) and the guide check of scripted feeds (bmGuideContact.h).
#include <gtest/gtest.h>

#include <cmath>

#include "bmFeedTrial.h"
#include "bmGuideContact.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"

namespace {

nlohmann::json TwoStepPlan() {
  return nlohmann::json::parse(R"({
    "name": "plan",
    "bone": {"type": "block", "size_mm": [40, 40, 12]},
    "trial": {"entry_mm": [1, 2, 0], "axis": [0, 0, 1], "feed_mm_per_rev": 0.1,
              "speed_rpm": 500, "clearance_mm": 7, "frame_s": 0.02},
    "voxmap_resolution": 80, "shell_resolution": 160,
    "steps": [
      {"name": "guide pin", "description": "the hole",
       "tool": {"type": "drill", "radius_mm": 3.5, "flute_length_mm": 12},
       "trial": {"depth_mm": 9, "clearance_mm": 0.5, "feed_mm_per_rev": 0.2},
       "shell_resolution": 96},
      {"name": "ream", "tool": {"type": "reamer"}, "trial": {"depth_mm": 1}}
    ],
    "planning": {"entry_mm": [1, 2, 0]}
  })");
}

TEST(PlanSteps, EachStepIsTheSceneWithItsToolAndTrial) {
  const bm::Scene plan = bm::Scene::FromJson(TwoStepPlan());
  ASSERT_EQ(plan.steps.size(), 2u);
  const bm::Scene pin = plan.Step(0), ream = plan.Step(1);
  EXPECT_EQ(pin.name, "plan: guide pin");
  EXPECT_EQ(pin.tool.at("type"), "drill");
  EXPECT_EQ(pin.shellResolution, 96);
  EXPECT_DOUBLE_EQ(pin.trial.depthMm, 9);
  EXPECT_DOUBLE_EQ(pin.trial.feedMmPerRev, 0.2);
  EXPECT_DOUBLE_EQ(pin.trial.speedRpm, 500); // the scene's, not overridden
  EXPECT_EQ(pin.trial.entry, Eigen::Vector3d(1, 2, 0));
  EXPECT_TRUE(pin.steps.empty());
  EXPECT_EQ(ream.tool.at("type"), "reamer");
  EXPECT_EQ(ream.shellResolution, 160);
  EXPECT_DOUBLE_EQ(ream.trial.clearanceMm, 7);
  EXPECT_DOUBLE_EQ(ream.trial.depthMm, 1);
  EXPECT_THROW(plan.Step(2), std::out_of_range);
  // The JSON round trip keeps the steps and the planning block.
  const bm::Scene again = bm::Scene::FromJson(plan.ToJson());
  ASSERT_EQ(again.steps.size(), 2u);
  EXPECT_EQ(again.steps[0].description, "the hole");
  EXPECT_EQ(again.Step(0).ToJson(), pin.ToJson());
  EXPECT_EQ(again.planning, plan.planning);
}

TEST(PlanSteps, ABadStepIsRefusedByItsNumberAndName) {
  nlohmann::json j = TwoStepPlan();
  j["steps"][1]["trial"]["feed_mm_per_rev"] = -1;
  try {
    bm::Scene::FromJson(j);
    FAIL() << "a negative feed in step 2 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("step 2 ('ream')"), std::string::npos) << e.what();
  }
  j = TwoStepPlan();
  j["steps"][0]["drill"] = 1;
  EXPECT_THROW(bm::Scene::FromJson(j), std::invalid_argument);
  j = TwoStepPlan();
  j["steps"] = nlohmann::json::array();
  EXPECT_THROW(bm::Scene::FromJson(j), std::invalid_argument);
}

// The reamer fed into a solid block: its nipple meets the bone 6 mm (its length) before the face
// does, and the feed stops there.
TEST(GuideContact, ANippleInSolidBoneStopsTheFeed) {
  const bm::Scene ream = bm::Scene::FromJson(TwoStepPlan()).Step(1);
  bm::MachiningSetup setup(ream, bm::MakeSceneBlock(ream));
  bm::FeedTrial trial(setup);
  ASSERT_TRUE(trial.Run());
  EXPECT_TRUE(trial.GuideBlocked());
  const double h = setup.Bone().Spacing();
  EXPECT_NEAR(trial.GuideStopDepthMm(), -6.0, 1.5 * h);
  ASSERT_EQ(trial.Warnings().size(), 2u); // the guide stopped, and nothing was removed
  EXPECT_NE(trial.Warnings()[0].find("guide nipple"), std::string::npos);
  EXPECT_NE(trial.Warnings()[1].find("removed no bone"), std::string::npos);
  const auto s = trial.Summary();
  EXPECT_TRUE(s.at("guide_blocked").get<bool>());
  EXPECT_NEAR(s.at("reached_depth_mm").get<double>(), -6.0, 1.5 * h);
}

// The same reamer after the guide-pin step: the nipple runs in the hole and the face reams to
// depth; the bone is carried from the first step to the second.
TEST(GuideContact, AfterThePinTheReamerReachesItsDepth) {
  const bm::Scene plan = bm::Scene::FromJson(TwoStepPlan());
  const bm::Scene pinScene = plan.Step(0), reamScene = plan.Step(1);
  bm::MachiningSetup pin(pinScene, bm::MakeSceneBlock(pinScene));
  bm::FeedTrial drill(pin);
  ASSERT_TRUE(drill.Run());
  EXPECT_FALSE(drill.GuideBlocked()); // a drill has no guide
  EXPECT_TRUE(drill.Warnings().empty()) << drill.Warnings().front();
  bm::MachiningSetup reamer(reamScene, pin.Bone());
  bm::GuideContact guide(reamer.Tool(), reamer.Bone());
  EXPECT_TRUE(guide.HasGuide());
  EXPECT_DOUBLE_EQ(guide.RadiusMm(), 3.0);
  bm::FeedTrial ream(reamer);
  ASSERT_TRUE(ream.Run());
  EXPECT_FALSE(ream.GuideBlocked()) << ream.Warnings().front();
  EXPECT_TRUE(ream.Warnings().empty());
  EXPECT_NEAR(ream.Summary().at("reached_depth_mm").get<double>(), 1.0, 0.02);
  EXPECT_GT(ream.Summary().at("removed_volume_mm3").get<double>(), 100.0);
}

} // namespace

namespace {

// A feed trial says when its path makes no sense: an entry beside the bone, a start inside it.
TEST(FeedTrialPath, AnEntryOutsideAllBoneAndAStartInsideBoneAreNamed) {
  nlohmann::json j = TwoStepPlan();
  j.erase("steps");
  j["tool"] = {{"type", "drill"}};
  j["trial"]["depth_mm"] = 0.5;
  j["trial"]["clearance_mm"] = 0.2;
  j["trial"]["frame_s"] = 0.05;
  j["trial"]["entry_mm"] = {60, 0, 0}; // beside the 40 mm block
  const bm::Scene beside = bm::Scene::FromJson(j);
  bm::MachiningSetup a(beside, bm::MakeSceneBlock(beside));
  bm::FeedTrial ta(a);
  ASSERT_TRUE(ta.Run());
  ASSERT_GE(ta.Warnings().size(), 1u);
  EXPECT_NE(ta.Warnings()[0].find("outside all bone"), std::string::npos) << ta.Warnings()[0];

  j["trial"]["entry_mm"] = {1, 2, -3}; // 3 mm inside the block
  const bm::Scene inside = bm::Scene::FromJson(j);
  bm::MachiningSetup b(inside, bm::MakeSceneBlock(inside));
  bm::FeedTrial tb(b);
  ASSERT_TRUE(tb.Run());
  ASSERT_GE(tb.Warnings().size(), 1u);
  EXPECT_NE(tb.Warnings()[0].find("starts inside bone"), std::string::npos) << tb.Warnings()[0];

  j["trial"]["entry_mm"] = {1, 2, 0}; // on the surface: nothing to say
  const bm::Scene good = bm::Scene::FromJson(j);
  bm::MachiningSetup c(good, bm::MakeSceneBlock(good));
  bm::FeedTrial tc(c);
  ASSERT_TRUE(tc.Run());
  EXPECT_TRUE(tc.Warnings().empty()) << tc.Warnings().front();
}

} // namespace
