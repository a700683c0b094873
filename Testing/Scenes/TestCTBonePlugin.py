"""A CT opened by a ParaView reader is machined through the plugin's "BM CT Bone" filter.

usage: pvbatch TestCTBonePlugin.py PLUGIN WORK_DIR

1. A block CT (4 x 4 x 3 mm of cortical bone at 1600 HU in air at -1000 HU, 0.2 mm voxels) is
   written as a .vti and opened with ParaView's own XML image reader.
2. "BM CT Bone" takes the reader as its input (no file name): the bone's volume is the block's
   (48 mm^3 within 2.5), its bounds hold the block, no error.
3. "BM Session" machines that bone (the drilling scene's drill from the suggested entry down the
   z axis): it must remove bone.
Exits non-zero on the first failed check.
"""
import json
import os
import sys
import time

from paraview.simple import LoadPlugin, XMLImageDataReader
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
from vtkmodules.util.vtkConstants import VTK_SHORT


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


def info(source, name):
    source.SMProxy.UpdatePropertyInformation()
    return source.GetProperty(name)[0]


def write_block_ct(path):
    image = vtkImageData()
    image.SetDimensions(40, 40, 30)
    image.SetSpacing(0.2, 0.2, 0.2)
    image.SetOrigin(-3.9, -3.9, -4.9)
    image.AllocateScalars(VTK_SHORT, 1)
    scalars = image.GetPointData().GetScalars()
    scalars.SetName("HU")
    n = 0
    for k in range(30):
        for j in range(40):
            for i in range(40):
                x, y, z = -3.9 + 0.2 * i, -3.9 + 0.2 * j, -4.9 + 0.2 * k
                bone = -2 < x < 2 and -2 < y < 2 and -3 < z < 0
                scalars.SetValue(n, 1600 if bone else -1000)
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
    print("BM CT Bone from a ParaView reader: OK")


if __name__ == "__main__":
    main()
