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
