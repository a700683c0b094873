#!/usr/bin/env bash
# Builds BoneMachining and runs the glenoid reaming demo (the README's demo command).
#
#   bash Utilities/demo.sh [OUT]     (default OUT = out/glenoid)
#
# Installs the Debian packages (Utilities/setup-debian.sh), configures and builds build/ (Ninja,
# Release), then runs `build/bin/bmsim run glenoid --out OUT`: the scripted reamer reams the
# built-in glenoid phantom 2 mm deep along its axis (about 30 s on 2 cores), and the report
# (OUT/report.html and report.md: removed volume, depth, forces and frame times over time, the
# reamed surface as reamed.vtp/.stl and a picture) is written. Prints where the report is.
# Rendering needs an X display; bmsim starts a private Xvfb when DISPLAY is unset.
# Environment: BM_JOBS (parallel build jobs, default 2).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="${1:-out/glenoid}"
jobs="${BM_JOBS:-2}"

bash Utilities/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

build/bin/bmsim run glenoid --out "$out"

echo
echo "demo.sh: outputs in $(cd "$out" && pwd):"
shopt -s nullglob
reports=("$out"/report.*)
if [ ${#reports[@]} -gt 0 ]; then
  for r in "${reports[@]}"; do echo "  report: $(cd "$(dirname "$r")" && pwd)/$(basename "$r")"; done
else
  ls -1 "$out" | sed 's/^/  /'
fi
