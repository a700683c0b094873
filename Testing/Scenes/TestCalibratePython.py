"""bmcalibrate (Utilities/Python) in ParaView's Python: the shipped published data calibrated from
pvpython give the shipped bovine set's coefficients, both methods' folds, and bad input a message.

usage: pvpython TestCalibratePython.py MODULE_DIR BMSIM DATA.csv SHIPPED_SET.json WORK_DIR
Exits non-zero on the first failed check.
"""
import json
import os
import sys

import paraview.simple  # noqa: F401  (runs inside ParaView's Python, as from its shell)

module_dir, bmsim, data, shipped, work = sys.argv[1:6]
sys.path.insert(0, module_dir)
import bmcalibrate  # noqa: E402


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)


# The bovine rows under the shipped set's name: the same fit as the file Resources ships.
out = os.path.join(work, "bovine")
r = bmcalibrate.calibrate(data, out, bones=["bovine femur"], name="drilling-bovine-orelaja2020",
                          bmsim=bmsim)
with open(shipped) as f:
    ref = json.load(f)
ours = r["coefficients"]
check(ours["name"] == "drilling-bovine-orelaja2020" and ours["calibrated"] is True,
      "coefficients.json names the set and says calibrated")
for part in ("lips", "chisel"):
    for key in ("kc_N_per_mm2", "kt_N_per_mm2"):
        got, want = ours[part][key][0], ref[part][key][0]
        check(abs(got - want) <= 1e-9 * abs(want),
              "%s %s %.6f N/mm^2 (shipped %.6f)" % (part, key, got, want))
check(os.path.isfile(r["files"]["chart"]), "chart.svg written")

# All six rows: one fold per condition for each method, none with a negative torque.
r = bmcalibrate.calibrate(data, os.path.join(work, "all"), bmsim=bmsim)
methods = [row["method"] for row in r["folds"]]
check(methods.count("lazar") == 6 and methods.count("zheng") == 6,
      "6 folds per method (%d lazar, %d zheng)" % (methods.count("lazar"), methods.count("zheng")))
check(all(float(row["min_torque_Nmm"]) > 0 for row in r["folds"]),
      "no fold predicts a negative torque")

# Bad input: an option refused before bmsim runs, bad data with bmsim's message.
try:
    bmcalibrate.calibrate(data, os.path.join(work, "bad"), chisel="round", bmsim=bmsim)
    check(False, "chisel='round' refused")
except ValueError as e:
    check("chisel must be one of" in str(e), "chisel='round' refused: %s" % e)
bad = os.path.join(work, "bad.csv")
with open(bad, "w") as f:
    f.write("tool,diameter_mm,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,2.5,0.05,fast,3\n")
try:
    bmcalibrate.calibrate(bad, os.path.join(work, "bad"), bmsim=bmsim)
    check(False, "a malformed speed refused")
except RuntimeError as e:
    check("bad.csv" in str(e) and "speed_rpm" in str(e), "a malformed speed refused: %s" % e)
check(not os.path.exists(os.path.join(work, "bad", "coefficients.json")),
      "nothing written for refused data")
