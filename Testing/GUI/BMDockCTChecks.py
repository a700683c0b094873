# BMDockCTChecks.py - the checks of BMDockCTReader.xml, run in paraview's Python shell (its path
# in $BM_DOCK_CT_CHECKS): a CT opened by one of ParaView's readers and selected is the CT the
# dock's CT section previews, shown as the bone's surface with the camera on it. The CT is an
# 8-bit display window written by the test (BMDockCTReaderData.cmake): a 20 x 20 x 10 mm block
# and a sphere of radius 5 mm, 1.5 mm apart, values 220 in a background of 40, 0.5 mm voxels,
# origin (10, 20, 30) mm. A failed check writes "BMDockCT: ..." to stderr and ends paraview with
# status 1. Units: mm, mm^3.
import math
import os

from paraview import servermanager, simple

bm_ct = {}


exec(open(os.path.join(os.path.dirname(os.environ["BM_DOCK_CT_CHECKS"]), "BMDockCheckSupport.py")).read())
bm_ct_fail, bm_ct_check = bm_check_support("BMDockCT")


@bm_ct_check
def bm_ct_open():
    """Opens the test's CT with ParaView's reader and selects it, as a user opening a file."""
    reader = simple.OpenDataFile(os.environ["BM_DOCK_CT_VTI"])
    bm_ct["reader"] = reader
    simple.Show(reader)
    simple.SetActiveSource(reader)
    simple.Render()


@bm_ct_check
def bm_ct_previewed(keep_all):
    """The dock's BM CT Bone reads the selected reader's image (not a file); its bone is the
    block and, with keep_all, the sphere too (volumes within 10 %); the bone shows as a surface
    (a Contour of the bone fraction, the image itself hidden), the camera frames it, and the view
    matches its baseline picture."""
    reader = bm_ct.get("reader")
    bone = simple.FindSource("BMCTBone1")
    if reader is None or bone is None:
        bm_ct_fail("no reader (%s) or no BMCTBone1 (%s)" % (reader, bone))
    if bone.Input is None or bone.Input.SMProxy != reader.SMProxy:
        bm_ct_fail("BMCTBone1 does not read the selected image (its input: %s)" % bone.Input)
    bone.SMProxy.UpdatePropertyInformation()
    error = bone.GetProperty("LastErrorInfo").GetElement(0)
    if error:
        bm_ct_fail("the preview failed: " + error)
    volume = bone.GetProperty("BoneVolumeInfo").GetElement(0)
    block, sphere = 20 * 20 * 10, 4.0 / 3.0 * math.pi * 5 ** 3
    want = block + (sphere if keep_all else 0.0)
    if abs(volume - want) > 0.1 * want:
        bm_ct_fail("bone volume %.0f mm^3, expected %.0f (keep all: %s)" % (volume, want, keep_all))
    surfaces = [s for name, s in simple.GetSources().items() if name[0].startswith("Contour")]
    if len(surfaces) != 1:
        bm_ct_fail("%d Contour sources, expected the preview's one surface" % len(surfaces))
    surface = surfaces[0]
    view = simple.GetActiveView()

    def shown(source):  # without making a representation where there is none
        rep = servermanager.GetRepresentation(source, view)
        return rep is not None and rep.Visibility

    if not shown(surface):
        bm_ct_fail("the bone's surface is hidden")
    if shown(bone):
        bm_ct_fail("the bone-fraction image is shown over its surface")
    b = surface.GetDataInformation().GetBounds()
    focal, position = view.CameraFocalPoint, view.CameraPosition
    if not all(b[2 * a] - 1e-6 <= focal[a] <= b[2 * a + 1] + 1e-6 for a in range(3)):
        bm_ct_fail("the camera looks at %s, outside the bone's bounds %s" % (list(focal), b))
    radius = 0.5 * math.sqrt(sum((b[2 * a + 1] - b[2 * a]) ** 2 for a in range(3)))
    distance = math.sqrt(sum((position[a] - focal[a]) ** 2 for a in range(3)))
    if not 0 < distance <= 2.0 * radius / math.sin(math.radians(view.CameraViewAngle / 2.0)):
        bm_ct_fail("the camera is %.1f mm from the bone: it does not frame it" % distance)
    os.write(2, ("BMDockCT: previewed %.0f mm^3 (keep all %s)\n" % (volume, keep_all)).encode())
    # What the user sees: the surface, framed (its baseline picture).
    bm_compare_screenshot(bm_ct_fail, view, "BMDockCTReader-all" if keep_all else "BMDockCTReader")
