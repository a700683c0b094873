#!/usr/bin/env bash
# Builds BoneMachining and runs the drilling demo (the README's demo command).
#
#   bash Utilities/demo.sh [OUT]     (default OUT = out/drilling)
#
# Installs the Debian packages (Utilities/setup-debian.sh), configures and builds build/ (Ninja,
# Release), then runs `build/bin/bmsim run drilling --out OUT` and prints where the report is.
# Environment: BM_JOBS (parallel build jobs, default 2).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="${1:-out/drilling}"
jobs="${BM_JOBS:-2}"

bash Utilities/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

build/bin/bmsim run drilling --out "$out"

echo
echo "demo.sh: outputs in $(cd "$out" && pwd):"
shopt -s nullglob
reports=("$out"/report.*)
if [ ${#reports[@]} -gt 0 ]; then
  for r in "${reports[@]}"; do echo "  report: $(cd "$(dirname "$r")" && pwd)/$(basename "$r")"; done
else
  ls -1 "$out" | sed 's/^/  /'
fi
