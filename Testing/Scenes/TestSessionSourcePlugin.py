"""Loads the BoneMachining plugin in pvpython and runs short live sessions with "BM Session".

usage: pvpython TestSessionSourcePlugin.py PLUGIN BASELINE_PNG WORK_DIR

1. Scripted session on the glenoid scene (voxmap 64, shell 113: grids 2:1), frames back to back:
   the live source is polled the way ParaView's GUI polls it (NeedsUpdateInfo, then an update)
   until the session pauses at the trial's end. Checks: several live updates, the removed volume
   never decreasing and positive at the end, the final depth within 0.5 mm of the scene's 2 mm
   (the proxy lags the stiff robot arm by thrust / stiffness), thrust positive, the bone and
   tool outputs non-empty, the tool's outer radius in its bounds.
2. A screenshot of the final cut (bone, from outside along the axis) compared with BASELINE_PNG
   by VTK's regression test (vtkTesting, threshold 0.15). A missing baseline is written and the
   test fails.
3. Mouse proxy, started in the background as the dock starts it (Start returns while the bone
   builds; Stop cancels that; started again, FinishStart runs it): a session whose tool follows
   ToolDepth; moved from 2 mm above the face to 0.5 mm below it, it must cut bone.
Exits non-zero on the first failed check.
"""
import os
import sys
import time

from paraview.simple import (CreateRenderView, LoadPlugin, OutputPort, Render, SaveScreenshot,
                             Show)
from vtkmodules.vtkTestingRendering import vtkTesting


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


def info(source, name):
    return source.GetProperty(name)[0]


def poll(source, timeout_s):
    """Polls the live source until its session pauses; returns the removed volumes seen."""
    seen = []
    start = time.time()
    while time.time() - start < timeout_s:
        source.SMProxy.UpdatePropertyInformation()
        if info(source, "NeedsUpdateInfo"):
            # What ParaView's live-source behaviour does: mark the proxy modified, update.
            source.SMProxy.MarkModified(source.SMProxy)
            source.UpdatePipeline()
            source.SMProxy.UpdatePropertyInformation()
            seen.append(info(source, "RemovedVolumeInfo"))
        elif info(source, "StateInfo") in (2, 3):  # paused (trial finished) or stopped
            break
        time.sleep(0.05)
    return seen


def finish_start(source):
    """FinishStart after a background start, then the source updated as the GUI would."""
    source.SMProxy.InvokeCommand("FinishStart")
    source.SMProxy.MarkModified(source.SMProxy)
    source.UpdatePipeline()
    source.SMProxy.UpdatePropertyInformation()


def main():
    check(len(sys.argv) == 4, "usage: TestSessionSourcePlugin.py PLUGIN BASELINE_PNG WORK_DIR")
    plugin, baseline, work = sys.argv[1], os.path.abspath(sys.argv[2]), sys.argv[3]
    os.makedirs(work, exist_ok=True)
    LoadPlugin(plugin, remote=False, ns=globals())
    check("BMSession" in globals(), "the plugin defines the BM Session source")

    session = globals()["BMSession"](Scene="glenoid", VoxmapResolution=64,
                                           ShellResolution=113, RealTime=0)
    session.UpdatePipeline()
    session.SMProxy.InvokeCommand("Start")
    seen = poll(session, 120)
    check(len(seen) >= 2, "the live source refreshed %d times during the session" % len(seen))
    check(all(b >= a for a, b in zip(seen, seen[1:])), "the removed volume never decreased")
    removed = info(session, "RemovedVolumeInfo")
    depth = info(session, "DepthInfo")
    thrust = info(session, "ThrustInfo")
    print("removed %.1f mm^3, depth %.3f mm, thrust %.1f N, frames %d, extract %.1f ms, frame p99 "
          "%.3f ms" % (removed, depth, thrust, info(session, "FrameInfo"),
                       info(session, "ExtractMsInfo"), info(session, "FrameMsP99Info")))
    check(removed > 1000.0, "removed volume %.1f mm^3 > 1000 mm^3" % removed)
    # The proxy lags the scripted robot by thrust / stiffness (2000 N/mm): ~0.25 mm here.
    check(1.5 < depth <= 2.0 + 1e-6, "final depth %.3f mm (scene: 2 mm, less the arm's lag)" % depth)
    check(thrust > 0.0, "thrust %.1f N positive" % thrust)
    bone = session.GetDataInformation(0)
    tool = session.GetDataInformation(1)
    check(bone.GetNumberOfCells() > 0, "the bone port has %d cells" % bone.GetNumberOfCells())
    check(tool.GetNumberOfCells() > 0, "the tool port has %d cells" % tool.GetNumberOfCells())
    b = tool.GetBounds()
    check(abs((b[5] - b[4]) - 36.5) < 0.01 and abs((b[3] - b[2]) - 36.5) < 0.01,
          "the reamer (36.5 mm) spans its bounds across the axis")

    view = CreateRenderView()
    view.OrientationAxesVisibility = 0
    view.Background = [0.12, 0.13, 0.16]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = Show(OutputPort(session, 0), view)
    display.DiffuseColor = [0.93, 0.89, 0.78]
    display.AmbientColor = [0.93, 0.89, 0.78]
    view.CameraPosition = [-300.0, 20.0, 40.0]  # outside the glenoid face, along its axis (-x)
    view.CameraFocalPoint = [-60.0, 20.0, 40.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 26.0
    Render(view)
    shot = os.path.join(work, "SessionSource.png")
    SaveScreenshot(shot, view, ImageResolution=[300, 300])
    if not os.path.exists(baseline):
        import shutil
        os.makedirs(os.path.dirname(baseline), exist_ok=True)
        shutil.copyfile(shot, baseline)
        check(False, "no baseline: wrote %s (check it and commit it)" % baseline)
    testing = vtkTesting()
    for arg in ("-V", baseline, "-T", work):
        testing.AddArgument(arg)
    check(testing.RegressionTest(shot, 0.15) == vtkTesting.PASSED,
          "the screenshot matches %s" % baseline)
    session.SMProxy.InvokeCommand("Stop")

    mouse = globals()["BMSession"](Scene="glenoid", VoxmapResolution=64,
                                         ShellResolution=113, RealTime=0, MaxFrames=4000,
                                         DeviceType="Mouse proxy", ToolDepth=-2.0)
    # Started in the background, as the dock starts it: Start returns while the bone builds,
    # the progress only grows, Stop cancels; started again, it builds and FinishStart runs it.
    mouse.StartInBackground = 1
    mouse.SMProxy.InvokeCommand("Start")
    mouse.SMProxy.UpdatePropertyInformation()
    check(info(mouse, "StartingInfo") == 1, "a background start returns while the bone builds")
    mouse.SMProxy.InvokeCommand("Stop")
    mouse.SMProxy.UpdatePropertyInformation()
    check(info(mouse, "StartingInfo") == 0, "Stop cancels a background start")
    finish_start(mouse)
    check(info(mouse, "LastErrorInfo") == "cancelled" and info(mouse, "StateInfo") == 0,
          "the cancelled start says so and runs no session ('%s', state %d)"
          % (info(mouse, "LastErrorInfo"), info(mouse, "StateInfo")))
    mouse.SMProxy.InvokeCommand("Start")
    progress, stages = [], set()
    start = time.time()
    while time.time() - start < 120:
        mouse.SMProxy.UpdatePropertyInformation()
        if not info(mouse, "StartingInfo"):
            break
        progress.append(info(mouse, "StartProgressInfo"))
        stages.add(info(mouse, "StartStageInfo"))
        time.sleep(0.01)
    print("background start: %d polls, progress %s, stages %s"
          % (len(progress), progress[-3:], sorted(s for s in stages if s)))
    check(all(b >= a for a, b in zip(progress, progress[1:])), "the start's progress only grows")
    finish_start(mouse)
    check(info(mouse, "LastErrorInfo") == "" and info(mouse, "StateInfo") == 1,
          "FinishStart runs the session the background start built ('%s', state %d)"
          % (info(mouse, "LastErrorInfo"), info(mouse, "StateInfo")))
    # Let the haptic thread pick up the starting pose (the proxy starts where the device is) and
    # run a while above the bone before the "mouse" moves into it.
    start = time.time()
    while time.time() - start < 60:
        mouse.SMProxy.MarkModified(mouse.SMProxy)
        mouse.UpdatePipeline()
        mouse.SMProxy.UpdatePropertyInformation()
        if info(mouse, "FrameInfo") >= 200:
            break
        time.sleep(0.02)
    check(info(mouse, "DepthInfo") < -1.9, "the mouse proxy starts above the face (%.3f mm)"
          % info(mouse, "DepthInfo"))
    mouse.ToolDepth = 0.5
    mouse.UpdatePipeline()
    poll(mouse, 120)
    mouse.SMProxy.MarkModified(mouse.SMProxy)
    mouse.UpdatePipeline()
    mouse.SMProxy.UpdatePropertyInformation()
    print("mouse proxy: removed %.1f mm^3, depth %.3f mm, thrust %.1f N"
          % (info(mouse, "RemovedVolumeInfo"), info(mouse, "DepthInfo"), info(mouse, "ThrustInfo")))
    check(info(mouse, "RemovedVolumeInfo") > 0.0, "the mouse proxy cut bone")
    mouse.SMProxy.InvokeCommand("Stop")
    print("OK")


main()
