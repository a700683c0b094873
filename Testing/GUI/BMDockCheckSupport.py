# BMDockCheckSupport.py - what the dock's GUI checks (BMDock*Checks.py, run in paraview's Python
# shell) share: a failure that ends paraview with status 1 after writing "PREFIX: message" to
# stderr, and a decorator that turns a check's exception into such a failure (the shell would
# print it and go on). A checks file runs it first:
#   exec(open(os.path.join(os.path.dirname(os.environ["BM_DOCK_..._CHECKS"]),
#                          "BMDockCheckSupport.py")).read())
#   bm_x_fail, bm_x_check = bm_check_support("BMDockX")
import functools
import os
import traceback


def bm_check_support(prefix):
    """(fail, check) for the checks whose messages start with `prefix`."""

    def fail(message):
        os.write(2, (prefix + ": " + message + "\n").encode())
        os._exit(1)

    def check(fn):
        @functools.wraps(fn)
        def checked(*args):
            try:
                fn(*args)
            except Exception:
                fail(fn.__name__ + " raised:\n" + traceback.format_exc())

        return checked

    return fail, check


def bm_compare_screenshot(fail, view, name, size=(400, 300), threshold=0.15):
    """Saves the view at `size` pixels as `name`.png in the test's folder and compares it with the
    baseline of that name in $BM_BASELINE_DIR by VTK's regression test (vtkTesting, as ParaView's
    own image tests; `threshold` is its error measure). A missing baseline is written there and
    fails (look at it, then commit it); a differing one fails and leaves the difference image in
    the test's folder."""
    from paraview import simple
    from vtkmodules.vtkTestingRendering import vtkTesting

    shot = os.path.abspath(name + ".png")
    simple.SaveScreenshot(shot, view, ImageResolution=list(size))
    baseline = os.path.join(os.environ["BM_BASELINE_DIR"], name + ".png")
    if not os.path.exists(baseline):
        import shutil

        shutil.copyfile(shot, baseline)
        fail("no baseline: wrote %s (look at it and commit it)" % baseline)
    testing = vtkTesting()
    for arg in ("-V", baseline, "-T", os.path.dirname(shot)):
        testing.AddArgument(arg)
    if testing.RegressionTest(shot, threshold) != vtkTesting.PASSED:
        fail("the view differs from %s (see %s and its difference image)" % (baseline, shot))
