"""The plugin's "BM Glenoid Plan" filter on the scapula phantom, as the Planning section uses it.

usage: pvbatch TestGlenoidPlanPlugin.py PLUGIN BMSIM WORK_DIR

1. `bmsim phantom scapula` writes the phantom's DICOM series and truth.json; `bmsim import
   --keep-all --resolution 160` turns it into a voxmap (scapula and humeral head, ~1 mm voxels)
   that ParaView's MetaImage reader opens.
2. "BM Glenoid Plan" on that voxmap: Friedman's version, the 3D version and the inclination
   within 1 deg of the phantom's truth, the glenoid centre within 1 mm, the plan scene with the
   guide-pin and reaming steps on the CT.
3. The trigonum moved as its handle widget moves it (Trigonum set, UseTrigonum on), turned 5 deg
   about the vertical through the glenoid line's midpoint: Friedman's version changes by 5 deg.
4. On "BM CT Bone"'s output (the scapula alone, no humeral head) the filter says "no glenoid
   found" and asks for the glenoid to be placed; a point on the face (FacePoint, as a click in
   the 3D view gives it) places the glenoid centre within 1.5 mm; with the glenoid centre and
   face normal given it measures the version within 1 deg again.
Exits non-zero on the first failed check.
"""
import json
import math
import os
import shutil
import subprocess
import sys

from paraview.simple import LoadPlugin, OpenDataFile, SetActiveSource


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


def info(proxy, name):
    proxy.SMProxy.UpdatePropertyInformation()
    prop = proxy.SMProxy.GetProperty(name)
    n = prop.GetNumberOfElements()
    values = [prop.GetElement(i) for i in range(n)]
    return values[0] if n == 1 else values


def turn_about_vertical(p, c, deg):
    a = math.radians(deg)
    x, y = p[0] - c[0], p[1] - c[1]
    return [c[0] + math.cos(a) * x - math.sin(a) * y, c[1] + math.sin(a) * x + math.cos(a) * y, p[2]]


def main():
    check(len(sys.argv) == 4, "usage: TestGlenoidPlanPlugin.py PLUGIN BMSIM WORK_DIR")
    plugin, bmsim, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    ct = os.path.join(work, "ct")
    voxmap = os.path.join(work, "bone.mha")
    subprocess.run([bmsim, "phantom", "scapula", "--quiet", "--out", ct], check=True)
    subprocess.run([bmsim, "import", ct, "--keep-all", "--resolution", "160", "--quiet",
                    "--out", voxmap], check=True)
    with open(os.path.join(ct, "truth.json")) as f:
        truth = json.load(f)

    LoadPlugin(plugin, remote=False, ns=globals())
    check("BMGlenoidPlan" in globals(), "the plugin defines BM Glenoid Plan")
    reader = OpenDataFile(voxmap)
    plan = globals()["BMGlenoidPlan"](Input=reader, CTFileName=ct)
    plan.UpdatePipeline()
    check(info(plan, "LastErrorInfo") == "", "no error (%r)" % info(plan, "LastErrorInfo"))
    friedman = info(plan, "FriedmanVersionInfo")
    version = info(plan, "Version3DInfo")
    inclination = info(plan, "InclinationInfo")
    check(abs(friedman - truth["friedman_version_deg"]) < 1.0,
          "Friedman version %.2f deg (truth %.2f)" % (friedman, truth["friedman_version_deg"]))
    check(abs(version - truth["version_3d_deg"]) < 1.0,
          "3D version %.2f deg (truth %.2f)" % (version, truth["version_3d_deg"]))
    check(abs(inclination - truth["inclination_deg"]) < 1.0,
          "inclination %.2f deg (truth %.2f)" % (inclination, truth["inclination_deg"]))
    centre = info(plan, "UsedGlenoidCentreInfo")
    error = math.dist(centre, truth["glenoid_centre_mm"])
    check(error < 1.0, "glenoid centre %s, %.2f mm from the truth" % (centre, error))
    scene = json.loads(info(plan, "PlanSceneInfo"))
    check([s["name"] for s in scene["steps"]] == ["guide pin", "ream"],
          "the plan scene holds the guide-pin and reaming steps")
    check(scene["bone"]["ct"]["ct"] == os.path.abspath(ct), "the plan scene's bone is the CT")
    check(plan.GetDataInformation().GetNumberOfPoints() > 70,
          "the output draws landmarks, rim, axis and normal")

    # The plan's result as DICOM beside its CT (ResultAsDicom, as bmsim run --dicom). The bone as
    # imported stands for both sessions' bones: nothing removed, the bone all remaining.
    result = os.path.join(work, "result")
    plan.ReportDirectory = result
    plan.ResultBeforeBone = voxmap
    plan.ResultAfterBone = voxmap
    plan.ResultSteps = json.dumps([{"step": 2, "name": "ream", "tool": "reamer",
                                    "summary": {"reached_depth_mm": 0.0}}])
    plan.ResultAsDicom = 1
    plan.SMProxy.InvokeCommand("WriteResult")
    check(info(plan, "ReportErrorInfo") == "", "the result as DICOM: no error (%r)"
          % info(plan, "ReportErrorInfo"))
    files = info(plan, "ReportFilesInfo").split("\n")
    for name in ("summary.json", "dicom/reamed-bone.seg.dcm", "dicom/plan.sr.dcm",
                 "dicom/glenoid_before.sc.dcm", "dicom/glenoid_after.sc.dcm"):
        check(name in files and os.path.getsize(os.path.join(result, name)) > 1000,
              "the result holds %s (%r)" % (name, files))
    with open(os.path.join(result, "dicom", "glenoid_after.sc.dcm"), "rb") as f:
        check(b"1.2.840.10008.5.1.4.1.1.7" in f.read(),
              "dicom/glenoid_after.sc.dcm is a Secondary Capture")
    with open(os.path.join(result, "dicom", "reamed-bone.seg.dcm"), "rb") as f:
        seg = f.read()
    check(seg[128:132] == b"DICM" and b"1.2.840.10008.5.1.4.1.1.66.4" in seg,
          "dicom/reamed-bone.seg.dcm is a DICOM Segmentation")
    with open(os.path.join(ct, sorted(n for n in os.listdir(ct) if n.endswith(".dcm"))[0]),
              "rb") as f:
        source = f.read()
    study = source.split(b"\x20\x00\x0d\x00", 1)[1][4:70].split(b"\x00")[0].strip()
    check(study in seg, "the Segmentation is in the CT's study")
    # A CT that is not a DICOM series has no series to write beside: refused, nothing written.
    plan.CTFileName = voxmap
    plan.UpdatePipeline()
    plan.ReportDirectory = os.path.join(work, "result-mha")
    plan.SMProxy.InvokeCommand("WriteResult")
    check("is not a DICOM series" in info(plan, "ReportErrorInfo") and
          not os.path.exists(os.path.join(work, "result-mha", "summary.json")),
          "a CT file that is not DICOM: %r" % info(plan, "ReportErrorInfo"))
    plan.CTFileName = ct
    plan.ResultAsDicom = 0
    plan.UpdatePipeline()

    # The CT read as BM CT Bone reads it (its bone specification: raw values, a series, exclude
    # points): the step scenes carry those settings, with the plan's region and seed.
    spec = {"ct": os.path.abspath(ct), "rawThreshold": 150, "series": "1.2.3",
            "exclude": [[1, 2, 3]], "roi": [0, 0, 0, 1, 1, 1], "keepAllComponents": True}
    plan.CTBoneSpecification = json.dumps(spec)
    plan.UpdatePipeline()
    for name in ("PinStepSceneInfo", "ReamStepSceneInfo", "PlanSceneInfo"):
        bone = json.loads(info(plan, name))["bone"]["ct"]
        check(bone["rawThreshold"] == 150 and bone["series"] == "1.2.3" and
              bone["exclude"] == [[1, 2, 3]], "%s reads the CT with its settings (%r)" % (name, bone))
        check(bone["roi"] != spec["roi"] and "keepAllComponents" not in bone,
              "%s keeps the plan's region, one bone (%r)" % (name, bone))
    plan.CTBoneSpecification = ""
    plan.UpdatePipeline()

    # Drag the trigonum (as the handle widget does: the property, then its Use flag) 5 deg about
    # the vertical through the midpoint of Friedman's glenoid line, where his scapular axis ends.
    trigonum = info(plan, "UsedTrigonumInfo")
    line = info(plan, "GlenoidLineInfo")
    mid = [(line[i] + line[i + 3]) / 2 for i in range(3)]
    plan.Trigonum = turn_about_vertical(trigonum, mid, 5.0)
    plan.UseTrigonum = 1
    plan.UpdatePipeline()
    moved = info(plan, "FriedmanVersionInfo")
    check(abs(abs(moved - friedman) - 5.0) < 0.1,
          "the trigonum turned 5 deg: Friedman version %.2f -> %.2f deg" % (friedman, moved))
    check(abs(info(plan, "Version3DInfo") - version) > 1.0, "the 3D version changes too")

    # The CT Bone output holds the scapula only: no joint to find, so the filter asks for the
    # landmarks; given the centre and normal it plans.
    SetActiveSource(None)  # the CT Bone reads FileName, no input image
    bone = globals()["BMCTBone"](FileName=ct, Resolution=160)
    bone.UpdatePipeline()
    on_ct = globals()["BMGlenoidPlan"](Input=bone)
    on_ct.UpdatePipeline()
    message = info(on_ct, "LastErrorInfo")
    check("no glenoid found" in message and "Click the face" in message,
          "one bone: %r" % message)
    # A point clicked on the face 3 mm above the centre: the glenoid traced around it.
    on_ct.FacePoint = [c + 3.0 * (k == 2) for k, c in enumerate(truth["glenoid_centre_mm"])]
    on_ct.UseFacePoint = 1
    on_ct.UpdatePipeline()
    check(info(on_ct, "LastErrorInfo") == "", "a face point: no error (%r)"
          % info(on_ct, "LastErrorInfo"))
    placed = math.dist(info(on_ct, "UsedGlenoidCentreInfo"), truth["glenoid_centre_mm"])
    check(placed < 1.5, "a face point gives the glenoid centre %.2f mm from the truth" % placed)
    on_ct.UseFacePoint = 0
    on_ct.GlenoidCentre = truth["glenoid_centre_mm"]
    on_ct.UseGlenoidCentre = 1
    on_ct.FaceNormal = truth["face_normal"]
    on_ct.UseFaceNormal = 1
    on_ct.UpdatePipeline()
    check(info(on_ct, "LastErrorInfo") == "", "landmarks given: no error")
    given = info(on_ct, "FriedmanVersionInfo")
    check(abs(given - truth["friedman_version_deg"]) < 1.0,
          "Friedman version with given landmarks %.2f deg" % given)

    # With every bone kept, BM CT Bone's output holds the joint: the glenoid is found from the CT
    # with no landmark given.
    bone.KeepAllBones = 1
    found = globals()["BMGlenoidPlan"](Input=bone)
    found.UpdatePipeline()
    check(info(found, "LastErrorInfo") == "", "all bones kept: the glenoid is found (%r)"
          % info(found, "LastErrorInfo"))
    detected = info(found, "FriedmanVersionInfo")
    check(abs(detected - truth["friedman_version_deg"]) < 1.0,
          "Friedman version from BM CT Bone with all bones %.2f deg (truth %.2f)"
          % (detected, truth["friedman_version_deg"]))
    print("TestGlenoidPlanPlugin: all checks passed")


if __name__ == "__main__":
    main()
