"""A faulty Touch driver does not take ParaView down: "BM Session" with the Touch device refuses to
start on the fake libHD (Testing/Logic/Session/FakeHD) in each of its fault modes, naming the step,
and this process lives on to try the next.

usage: pvbatch TestTouchFaultsPlugin.py PLUGIN FAKE_LIBHD

The fault is chosen by FAKEHD_FAULT, which the fake reads when a process loads it; the session
source tries the driver in a child process first (bm::ProbeTouch), so only that child meets it.
Exits non-zero on the first failed check.
"""
import os
import sys

from paraview.simple import LoadPlugin


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


def main():
    check(len(sys.argv) == 3, "usage: TestTouchFaultsPlugin.py PLUGIN FAKE_LIBHD")
    plugin, fake = sys.argv[1], sys.argv[2]
    os.environ["BM_LIBHD"] = fake
    LoadPlugin(plugin, remote=False, ns=globals())
    cases = [("constructor", "crashed during dlopen"),
             ("init", "crashed during hdInitDevice"),
             ("old-version", "older than 3"),
             ("enable", "crashed during hdEnable(HD_FORCE_OUTPUT)"),
             ("servo", "crashed during the servo callback")]
    for fault, needle in cases:
        os.environ["FAKEHD_FAULT"] = fault
        session = globals()["BMSession"](Scene="drilling", DeviceType="Touch", RealTime=0)
        session.SMProxy.InvokeCommand("Start")
        session.SMProxy.UpdatePropertyInformation()
        error = session.GetProperty("LastErrorInfo")[0]
        check(needle in error, "%s: the session did not start: %s" % (fault, error))
        check(session.GetProperty("StateInfo")[0] in (0, 3),
              "%s: no session runs (state %d)" % (fault, session.GetProperty("StateInfo")[0]))
    print("OK")


main()
