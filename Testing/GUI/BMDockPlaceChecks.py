# BMDockPlaceChecks.py - the checks of BMDockPlacePlan.xml, run in paraview's Python shell (its
# path in $BM_DOCK_PLACE_CHECKS): the glenoid placed by a click on the face in the 3D view, where
# detection finds no glenoid (the preview keeps the scapula alone), on the phantom's 8-bit CT
# opened with ParaView's reader. The truth is the phantom's (truth.json beside ct.nrrd in
# ct-scapula-8bit). A failed check writes "BMDockPlace: ..." to stderr and ends paraview with
# status 1. Units: mm, deg.
import json
import math
import os

from paraview import simple

bm_place = {}


exec(open(os.path.join(os.path.dirname(os.environ["BM_DOCK_PLACE_CHECKS"]), "BMDockCheckSupport.py")).read())
bm_place_fail, bm_place_check = bm_check_support("BMDockPlace")

# The cut bone Save bone writes after the plan's steps, and a fresh paraview starts again from
# (BMDockRestart.xml).
BM_PLACE_SAVED = "place-saved.nrrd"


def _plan():
    """The dock's BM Glenoid Plan filter."""
    plans = [s for s in simple.GetSources().values()
             if s.SMProxy.GetXMLName() == "BMGlenoidPlanFilter"]
    if len(plans) != 1:
        bm_place_fail("expected one BM Glenoid Plan filter, found %d" % len(plans))
    return plans[0]


def _truth():
    with open(os.path.join("ct-scapula-8bit", "truth.json")) as f:
        return json.load(f)


# Limits from the scan: 2.5 mm slices (1.4 mm pixels) blur the face by half a slice, 1.25 mm,
# over a glenoid 40 mm high: the centre within 2 mm, the normal and the angles within
# atan(1.25 / 20) = 3.6 deg.
BM_PLACE_CENTRE_MM = 2.0
BM_PLACE_ANGLE_DEG = 3.6


@bm_place_check
def bm_place_open():
    """Opens the CT with ParaView's reader and selects it, as a user opening a file."""
    reader = simple.OpenDataFile(os.path.abspath(os.path.join("ct-scapula-8bit", "ct.nrrd")))
    bm_place["reader"] = reader
    simple.Show(reader)
    simple.SetActiveSource(reader)
    simple.Render()


@bm_place_check
def bm_place_camera():
    """Looks at the glenoid face from outside the joint, along its normal: the view's centre is
    the glenoid centre (as a surgeon turns the bone to see the face before clicking it)."""
    t = _truth()
    c, n = t["glenoid_centre_mm"], t["face_normal"]
    view = simple.GetActiveView()
    simple.Render(view)  # simple's first render of a view resets its camera: not after ours
    view.CameraFocalPoint = c
    view.CameraPosition = [c[k] + 150.0 * n[k] for k in range(3)]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelProjection = 0
    simple.Render(view)


@bm_place_check
def bm_place_planned():
    """The plan filter used the clicked point: the glenoid centre, the face normal, the 3D version
    and inclination within the scan's limits of the truth; its glyphs are shown coloured by their
    own Colors array (every part); the camera then looks down the plan."""
    t = _truth()
    plan = _plan()
    plan.SMProxy.UpdatePropertyInformation()
    error = plan.GetProperty("LastErrorInfo").GetElement(0)
    if error:
        bm_place_fail("the plan failed: " + error)
    if plan.UseFacePoint != 1:
        bm_place_fail("the plan does not use a face point")
    c = [plan.GetProperty("UsedGlenoidCentreInfo").GetElement(k) for k in range(3)]
    n = [plan.GetProperty("UsedFaceNormalInfo").GetElement(k) for k in range(3)]
    d = math.dist(c, t["glenoid_centre_mm"])
    if d > BM_PLACE_CENTRE_MM:
        bm_place_fail("glenoid centre %s is %.2f mm from the truth" % (c, d))
    cosine = sum(a * b for a, b in zip(n, t["face_normal"]))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, cosine))))
    if angle > BM_PLACE_ANGLE_DEG:
        bm_place_fail("face normal %s is %.2f deg from the truth" % (n, angle))
    for info, key in (("Version3DInfo", "version_3d_deg"), ("InclinationInfo", "inclination_deg")):
        v = plan.GetProperty(info).GetElement(0)
        if abs(v - t[key]) > BM_PLACE_ANGLE_DEG:
            bm_place_fail("%s %.2f against the truth's %.2f" % (info, v, t[key]))
    repr_ = simple.GetDisplayProperties(plan)
    if repr_.Visibility != 1 or repr_.ColorArrayName[1] != "Colors" or repr_.MapScalars != 0:
        bm_place_fail("the plan's glyphs are not shown in their colours (%s, map %s)"
                      % (repr_.ColorArrayName, repr_.MapScalars))
    parts = plan.CellData["Part"].GetRange()
    if parts[0] != 0 or parts[1] < 4:
        bm_place_fail("the glyphs' parts run %s" % (parts,))
    view = simple.GetActiveView()
    camera = plan.GetProperty("PlanCameraInfo")
    focal = [camera.GetElement(k) for k in range(3)]
    if math.dist(list(view.CameraFocalPoint), focal) > 1e-6:
        bm_place_fail("the camera does not look at the plan (%s, not %s)"
                      % (list(view.CameraFocalPoint), focal))


@bm_place_check
def bm_place_sliced():
    """Axial slice: a Slice of the CT as read (the reader's image), through the glenoid centre,
    normal z."""
    plan = _plan()
    slices = [s for name, s in simple.GetSources().items() if name[0].startswith("Slice")]
    if len(slices) != 1:
        bm_place_fail("expected one slice, found %d" % len(slices))
    s = slices[0]
    if s.Input.SMProxy != bm_place["reader"].SMProxy:
        bm_place_fail("the slice cuts %s, not the CT as read" % s.Input)
    c = [plan.GetProperty("UsedGlenoidCentreInfo").GetElement(k) for k in range(3)]
    if math.dist(list(s.SliceType.Origin), c) > 1e-6 or list(s.SliceType.Normal) != [0, 0, 1]:
        bm_place_fail("the slice is at %s normal %s" % (list(s.SliceType.Origin),
                                                        list(s.SliceType.Normal)))
    if s.GetDataInformation().GetNumberOfPoints() < 100:
        bm_place_fail("the slice is empty")


@bm_place_check
def bm_place_reported(folder):
    """Write report wrote the plan as bmsim plan writes it: the scenes and the report, planned,
    the glenoid centre 'user face point'."""
    for name in ("plan.json", "step1-guide-pin.json", "step2-ream.json", "plan_report.md",
                 "plan_report.html", "plan_report.json"):
        if not os.path.isfile(os.path.join(folder, name)):
            bm_place_fail("the report folder has no " + name)
    with open(os.path.join(folder, "plan_report.json")) as f:
        report = json.load(f)
    if report.get("status") != "planned":
        bm_place_fail("the report's status is %s" % report.get("status"))
    with open(os.path.join(folder, "plan.json")) as f:
        plan = json.load(f)
    source = plan["planning"]["landmarks"].get("source", {})
    if source.get("glenoid_centre") != "user face point":
        bm_place_fail("the plan's centre came from %s" % source)


@bm_place_check
def bm_place_drag_trigonum():
    """Moves the plan filter's trigonum as dragging its handle in the 3D view does (the property,
    not the dock): to (-36.75, 88.06, 60.0) mm, 10 mm posterior of the phantom's."""
    plan = _plan()
    bm_place["version_before"] = plan.GetProperty("FriedmanVersionInfo").GetElement(0)
    plan.Trigonum = [-36.75, 88.06, 60.0]


@bm_place_check
def bm_place_dragged():
    """The dock followed the dragged handle: the plan ran again with the moved trigonum (used as
    given) and Friedman's version changed."""
    plan = _plan()
    plan.SMProxy.UpdatePropertyInformation()
    used = [plan.GetProperty("UsedTrigonumInfo").GetElement(k) for k in range(3)]
    if math.dist(used, [-36.75, 88.06, 60.0]) > 1e-6:
        bm_place_fail("the plan did not take the dragged trigonum (it used %s)" % used)
    after = plan.GetProperty("FriedmanVersionInfo").GetElement(0)
    if abs(after - bm_place["version_before"]) < 2.0:
        bm_place_fail("Friedman's version did not follow the trigonum (%.2f -> %.2f deg)"
                      % (bm_place["version_before"], after))


@bm_place_check
def bm_place_result(folder):
    """Write result wrote the plan's result as bmsim run writes one: both steps with their
    figures (stopped short of their depths, and said so), the outcome on the bone (bone removed
    by the pin and the reamer), the pictures."""
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    steps = summary.get("steps", [])
    if [s.get("tool") for s in steps] != ["drill", "reamer"]:
        bm_place_fail("the result's steps are %s" % [s.get("tool") for s in steps])
    # The sessions ran a few seconds, not to their planned depths: the result says so.
    if summary.get("completed") is not False or not any(
            "stopped at" in w for s in steps for w in s["summary"].get("warnings", [])):
        bm_place_fail("the result does not say the steps stopped short: completed %s, steps %s"
                      % (summary.get("completed"), steps))
    outcome = summary.get("outcome")
    if not outcome or not outcome.get("removed_volume_mm3", 0) > 0:
        bm_place_fail("the result has no outcome with bone removed: %s" % outcome)
    for name in ("plan_result.md", "plan_result.html", "glenoid_before.png", "glenoid_after.png"):
        if not os.path.isfile(os.path.join(folder, name)):
            bm_place_fail("the result folder has no " + name)


@bm_place_check
def bm_place_pictured():
    """The 3D view as the surgeon sees the plan (the CT bone, the plan's glyphs, the camera down
    the planned axis) matches its baseline picture."""
    bm_compare_screenshot(bm_place_fail, simple.GetActiveView(), "BMDockPlacePlan")


def _session():
    """The dock's session (a new one replaces the last)."""
    sessions = [s for s in simple.GetSources().values()
                if s.SMProxy.GetXMLName() == "BMSessionSource"]
    if len(sessions) != 1:
        bm_place_fail("expected one BM Session source, found %d" % len(sessions))
    return sessions[0]


def _trial(source):
    """The session's trial (entry world mm, unit axis) as lists, from its information
    properties."""
    source.SMProxy.UpdatePropertyInformation()
    entry = [source.GetProperty("SessionEntryInfo").GetElement(k) for k in range(3)]
    axis = [source.GetProperty("SessionAxisInfo").GetElement(k) for k in range(3)]
    if axis == [0.0, 0.0, 0.0]:
        bm_place_fail("the session has no trial")
    return entry, axis


def _tool_pose(source, entry, axis):
    """The shown tool against a trial: the angle (deg) between the tool's axis (its mesh is rings
    about it: the principal axis of its points) and `axis`, and its centre's distance from the
    line along `axis` through `entry` and along it (mm)."""
    source.UpdatePipeline()
    points = source.GetClientSideObject().GetOutputDataObject(1).GetPoints()
    n = points.GetNumberOfPoints() if points else 0
    if n == 0:
        bm_place_fail("the session shows no tool")
    import numpy
    p = numpy.array([points.GetPoint(i) for i in range(n)])
    mean = p.mean(axis=0)
    values, vectors = numpy.linalg.eigh(numpy.cov((p - mean).T))
    # The distinct eigenvalue's vector (the other two are equal, the rings' plane).
    gaps = [abs(values[k] - values[(k + 1) % 3]) + abs(values[k] - values[(k + 2) % 3])
            for k in range(3)]
    tool_axis = vectors[:, int(numpy.argmax(gaps))]
    angle = math.degrees(math.acos(min(1.0, abs(float(numpy.dot(tool_axis, axis))))))
    rel = mean - numpy.array(entry)
    along = float(numpy.dot(rel, axis))
    off = math.sqrt(max(0.0, float(numpy.dot(rel, rel)) - along * along))
    os.write(2, ("BMDockPlace: %s's tool %.3f deg off the axis, centre %.2f mm off it, %.2f mm "
                 "along\n" % (source.GetXMLLabel(), angle, off, along)).encode())
    return angle, off, along


def _saved_trial(path):
    """The trial saved in a voxmap file's NRRD header (bm_trial_entry_mm, bm_trial_axis:
    hexadecimal floats), as (entry, axis), or None."""
    fields = {}
    with open(path, "rb") as f:
        for raw in f:
            line = raw.decode("latin-1").rstrip("\n")
            if not line:
                break  # the header ends at the first blank line
            if ":=" in line:
                key, value = line.split(":=", 1)
                fields[key] = value
    if "bm_trial_entry_mm" not in fields:
        return None
    return ([float.fromhex(v) for v in fields["bm_trial_entry_mm"].split()],
            [float.fromhex(v) for v in fields["bm_trial_axis"].split()])


@bm_place_check
def bm_place_saved():
    """Save bone wrote the reaming session's bone with the trial it was cut on: its entry and
    axis, exactly."""
    if not os.path.isfile(BM_PLACE_SAVED):
        bm_place_fail("Save bone wrote no " + BM_PLACE_SAVED)
    trial = _saved_trial(BM_PLACE_SAVED)
    if trial is None:
        bm_place_fail(BM_PLACE_SAVED + " carries no trial")
    entry, axis = _trial(_session())
    _tool_pose(_session(), entry, axis)
    if trial != (entry, axis):
        bm_place_fail("the saved trial %s is not the session's %s" % (trial, (entry, axis)))


@bm_place_check
def bm_place_restarted():
    """A fresh paraview started a session from the saved bone, at the entry and axis saved with
    it (bit for bit), the reamer on that axis clear of the cut, saying why it starts further
    out."""
    source = _session()
    source.SMProxy.UpdatePropertyInformation()
    if source.GetProperty("SessionTrialSourceInfo").GetElement(0) != "the bone file's":
        bm_place_fail("the trial came from %s, not the saved bone"
                      % source.GetProperty("SessionTrialSourceInfo").GetElement(0))
    entry, axis = _trial(source)
    saved = _saved_trial(BM_PLACE_SAVED)
    if saved is None or [entry, axis] != list(saved):
        bm_place_fail("the restarted trial %s is not the saved %s" % ((entry, axis), saved))
    # The reamer shown lies on the saved axis, outside the bone: the built-in scene's 1.5 mm
    # clearance puts it in the reamed rim, so the session starts it further out and says so
    # (without that, the contact pushed it 18 mm sideways in its first frames). Once it feeds
    # into its cut, the cut's lateral forces move it by tenths of a millimetre: within 1 mm.
    note = source.GetProperty("SessionStartNoteInfo").GetElement(0)
    if "further out along its axis" not in note:
        bm_place_fail("the session does not say why its start moved: '%s'" % note)
    angle, off, along = _tool_pose(source, entry, axis)
    if angle > 0.5 or off > 1.0 or along <= 0:
        bm_place_fail("the reamer is %.2f deg and %.3f mm off the saved axis, %.2f mm along it"
                      % (angle, off, along))
