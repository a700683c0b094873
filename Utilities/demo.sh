#!/usr/bin/env bash
# Sets up a fresh machine, builds BoneMachining and runs the main job (the README's first command):
# the glenoid plan and its rehearsal on the scapula phantom.
#
#   bash Utilities/demo.sh [OUT]     (default OUT = out/demo)
#
# 1. Debian packages (Utilities/setup-debian.sh), then build/ (Ninja, Release).
# 2. `bmsim plan phantom --out OUT/plan`: the scapula phantom (12 deg retroversion, 8 deg superior
#    inclination, humeral head 4 mm across the joint) written as a DICOM series and imported; the
#    glenoid found and measured (Friedman 2D and 3D version, inclination, size, curvature); the
#    reaming axis proposed at 0 deg version and inclination; plan.json and the pre-operative report
#    (plan_report.html/.md/.json).
# 3. `bmsim run OUT/plan/plan.json --out OUT/run`: the guide-pin hole drilled along the axis, then
#    the nipple-guided reamer 2 mm deep, on the same bone; each step's report (forces over time,
#    the cut surface and its picture) and the plan's result (plan_result.html/.md: removed cortical
#    and cancellous bone, the reamed face against the target, medialisation, baseplate seating,
#    bone beyond the pin and peg). About 2 minutes on 2 cores after the build.
# Rendering needs an X display; bmsim starts a private Xvfb when DISPLAY is unset.
# Environment: BM_JOBS (parallel build jobs, default 2).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="${1:-out/demo}"
jobs="${BM_JOBS:-2}"

bash Utilities/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

rm -rf "$out/plan"
build/bin/bmsim plan phantom --out "$out/plan"
build/bin/bmsim run "$out/plan/plan.json" --out "$out/run"

echo
echo "demo.sh: the pre-operative plan: $(cd "$out/plan" && pwd)/plan_report.html"
echo "demo.sh: the rehearsal:          $(cd "$out/run" && pwd)/plan_result.html"
