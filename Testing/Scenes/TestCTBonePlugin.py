"""A CT opened by a ParaView reader is machined through the plugin's "BM CT Bone" filter.

usage: pvbatch TestCTBonePlugin.py PLUGIN WORK_DIR

1. A block CT (4 x 4 x 3 mm of cortical bone at 1600 HU in air at -1000 HU, 0.2 mm voxels) is
   written as a .vti and opened with ParaView's own XML image reader.
2. "BM CT Bone" takes the reader as its input (no file name): the bone's volume is the block's
   (48 mm^3 within 2.5), its bounds hold the block, no error.
3. "BM Session" machines that bone (the drilling scene's drill from the suggested entry down the
   z axis): it must remove bone.
4. The same block as a windowed 8-bit image (0 = -1000 HU, 255 = 1550 HU, no rescale), read by
   ParaView: refused as "not Hounsfield units" with the filter's intensity modes named; read as
   raw values (threshold 128) and through a given HU mapping (10 x value - 1000) it gives the
   block's volume, the import report naming the mapping.
Exits non-zero on the first failed check.
"""
import json
import os
import sys
import time

from paraview.simple import LoadPlugin, XMLImageDataReader
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
from vtkmodules.util.vtkConstants import VTK_SHORT, VTK_UNSIGNED_CHAR


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


def info(source, name):
    source.SMProxy.UpdatePropertyInformation()
    return source.GetProperty(name)[0]


def write_block_ct(path, windowed=False):
    """The block CT in HU (short), or windowed to 8 bits: value = (HU + 1000) / 10."""
    image = vtkImageData()
    image.SetDimensions(40, 40, 30)
    image.SetSpacing(0.2, 0.2, 0.2)
    image.SetOrigin(-3.9, -3.9, -4.9)
    image.AllocateScalars(VTK_UNSIGNED_CHAR if windowed else VTK_SHORT, 1)
    scalars = image.GetPointData().GetScalars()
    scalars.SetName("HU")
    n = 0
    for k in range(30):
        for j in range(40):
            for i in range(40):
                x, y, z = -3.9 + 0.2 * i, -3.9 + 0.2 * j, -4.9 + 0.2 * k
                bone = -2 < x < 2 and -2 < y < 2 and -3 < z < 0
                hu = 1600 if bone else -1000
                scalars.SetValue(n, min(255, (hu + 1000) // 10) if windowed else hu)
                n += 1
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    check(writer.Write() == 1, "wrote the block CT to %s" % path)


def main():
    check(len(sys.argv) == 3, "usage: TestCTBonePlugin.py PLUGIN WORK_DIR")
    plugin, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    LoadPlugin(plugin, remote=False, ns=globals())
    check("BMCTBone" in globals() and "BMSession" in globals(),
          "the plugin defines BM CT Bone and BM Session")
    path = os.path.join(work, "block.vti")
    write_block_ct(path)
    reader = XMLImageDataReader(FileName=[path])
    reader.UpdatePipeline()

    bone = globals()["BMCTBone"](Input=reader, ThresholdHU=500, Resolution=48)
    bone.UpdatePipeline()
    error = bone.SMProxy.GetProperty("LastErrorInfo")
    bone.SMProxy.UpdatePropertyInformation()
    check(error.GetElement(0) == "", "no error (%r)" % error.GetElement(0))
    volume = info(bone, "BoneVolumeInfo")
    check(abs(volume - 48.0) < 2.5, "bone volume %.2f mm^3 (block: 48 mm^3)" % volume)
    bounds = bone.GetDataInformation().GetBounds()
    check(bounds[0] < -1.9 and bounds[1] > 1.9 and bounds[4] < -2.9 and bounds[5] > -0.1,
          "the preview covers the block: %s" % (bounds,))
    spec_property = bone.SMProxy.GetProperty("BoneSpecificationInfo")
    spec = json.loads(spec_property.GetElement(0))
    check(os.path.exists(spec["ct"]), "the specification names a CT copy: %s" % spec["ct"])
    entry = bone.GetProperty("SuggestedEntryInfo")
    entry = [entry[0], entry[1], entry[2]]
    check(abs(entry[2]) < 0.2, "the suggested entry %s is on the top face" % (entry,))

    session = globals()["BMSession"](Scene="drilling", VoxmapResolution=64, ShellResolution=128,
                                     RealTime=0, MaxFrames=1500, OverrideTrial=1, Entry=entry,
                                     Axis=[0.0, 0.0, 1.0])
    session.BoneCT = spec_property.GetElement(0)
    session.UpdatePipeline()
    session.SMProxy.InvokeCommand("Start")
    start = time.time()
    while time.time() - start < 120:
        if info(session, "NeedsUpdateInfo"):
            session.SMProxy.MarkModified(session.SMProxy)
            session.UpdatePipeline()
        elif info(session, "StateInfo") in (2, 3):
            break
        time.sleep(0.02)
    removed = info(session, "RemovedVolumeInfo")
    check(removed > 0.05, "the session removed %.3f mm^3 of the CT's bone" % removed)
    session.SMProxy.InvokeCommand("Stop")

    windowed_path = os.path.join(work, "block-8bit.vti")
    write_block_ct(windowed_path, windowed=True)
    windowed = XMLImageDataReader(FileName=[windowed_path])
    windowed.UpdatePipeline()
    bone8 = globals()["BMCTBone"](Input=windowed, ThresholdHU=500, Resolution=48)
    bone8.UpdatePipeline()
    bone8.SMProxy.UpdatePropertyInformation()
    message = bone8.SMProxy.GetProperty("LastErrorInfo").GetElement(0)
    check("not Hounsfield units" in message and "Intensity mode" in message,
          "a windowed 8-bit image is refused naming the intensity modes (%r)" % message)
    for mode, settings, mapping in ((1, {"RawThreshold": 128}, "raw values"),
                                    (2, {"HUMapping": [10.0, -1000.0]}, "given mapping")):
        bone8.IntensityMode = mode
        for name, value in settings.items():
            setattr(bone8, name, value)
        bone8.UpdatePipeline()
        bone8.SMProxy.UpdatePropertyInformation()
        error = bone8.SMProxy.GetProperty("LastErrorInfo").GetElement(0)
        check(error == "", "intensity mode %d imports (%r)" % (mode, error))
        volume = info(bone8, "BoneVolumeInfo")
        check(abs(volume - 48.0) < 2.5, "mode %d: bone volume %.2f mm^3 (block: 48 mm^3)"
              % (mode, volume))
        report = bone8.SMProxy.GetProperty("ImportReportInfo").GetElement(0)
        check(mapping in report, "mode %d: the import report names the %s" % (mode, mapping))
        spec = json.loads(bone8.SMProxy.GetProperty("BoneSpecificationInfo").GetElement(0))
        check(("rawThreshold" in spec) == (mode == 1) and ("huMapping" in spec) == (mode == 2),
              "mode %d: the session's bone specification carries the mapping: %s" % (mode, spec))
    print("BM CT Bone from a ParaView reader: OK")


if __name__ == "__main__":
    main()
