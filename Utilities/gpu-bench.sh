#!/usr/bin/env bash
# gpu-bench.sh - the OpenCL backend measured on a GPU machine that has no package access
# (Docs/Performance.md, "The OpenCL backend on a GPU").
#
#   bash Utilities/gpu-bench.sh package DIR        # on a Debian 12 machine with the project's
#                                                  # packages: a Logic-only Release build (OpenCL,
#                                                  # CT import, no ParaView) and the shared
#                                                  # libraries it needs, into DIR
#   bash Utilities/gpu-bench.sh run DIR OUT [STEPS] # on the GPU machine, from the repository's
#                                                  # root: the checks and benchmarks, into OUT
#
# STEPS (default all, in this order): devices, identity (the OpenCL identity and session tests on
# the default device, a GPU when there is one), grid-gpu (the paper's grid, both methods, OpenCL),
# session (the glenoid session, OpenCL at voxmap 192 and 256, the CPU backend at 192), grid-cpu
# (the paper's grid, both methods, the CPU backend on every core), tune (not by default: the
# GPU's work split against the largest cell, then the lazar grid with the best). Each step has a time limit, cut
# to what is left of BM_GPU_DEADLINE_S (default 600 s from the start); OUT gets two files, log.txt
# and results.tar.gz (every step's files), rewritten after each step, so a run cut short keeps
# what it measured. BM_GPU_FRAMES / BM_GPU_WARMUP set the grid's frames per cell
# (default 300 / 50), BM_GPU_GRID extra options of the grid's runs (a smaller grid to try the
# script: "--shells 128 --voxmaps 128"); BM_GPU_SESSION_S the session's seconds (default 5).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

package() {
  local dir="$1" build="$here/build-gpu"
  # Portable code (the GPU machine's processor is not this one's): x86-64-v3 without FMA, so that
  # the kernels' C++ twins round as the kernels do (the top-level CMakeLists.txt explains).
  cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBM_WITH_PARAVIEW=OFF \
    -DBM_WITH_ITK=ON -DBM_WITH_OPENCL=ON -DBM_WITH_HDF5=OFF -DBM_BUILD_TESTING=ON \
    -DBM_BUILD_BENCHMARKS=OFF -DBM_NATIVE=OFF -DCMAKE_CXX_FLAGS="-march=x86-64-v3 -mno-fma" ||
    return 1
  cmake --build "$build" -j "${BM_JOBS:-2}" --target bmsim BMOpenCLTests || return 1
  rm -rf "$dir"
  mkdir -p "$dir/bin" "$dir/lib" "$dir/lib-std"
  cp "$build/bin/bmsim" "$build/Testing/Logic/BMOpenCLTests" "$dir/bin/"
  # Every library the two programs load but the C library's own (the GPU machine has a C library
  # at least as new); the C++ runtime apart, used only where the machine's is older.
  ldd "$dir/bin/bmsim" "$dir/bin/BMOpenCLTests" | awk '$3 ~ /^\// {print $3}' | sort -u |
    while read -r lib; do
      case "$(basename "$lib")" in
      libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux*) ;;
      libstdc++.so* | libgcc_s.so*) cp -L "$lib" "$dir/lib-std/" ;;
      *) cp -L "$lib" "$dir/lib/" ;;
      esac
    done
  du -sh "$dir"
}

run() {
  local dir out steps
  dir="$(cd "$1" && pwd)"
  out="$2"
  steps="${3:-devices,identity,grid-gpu,session,grid-cpu}"
  local work
  work="$(mktemp -d)"
  mkdir -p "$out" "$work/results"
  local log="$out/log.txt" res="$work/results"
  : >"$log"
  say() { echo "$@" | tee -a "$log"; }
  pack() { tar -czf "$out/results.tar.gz.part" -C "$work" results 2>/dev/null &&
    mv "$out/results.tar.gz.part" "$out/results.tar.gz"; }
  local deadline=$((SECONDS + ${BM_GPU_DEADLINE_S:-600}))
  export LD_LIBRARY_PATH="$dir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  if ! "$dir/bin/bmsim" --version >/dev/null 2>&1; then
    export LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$dir/lib-std"
    say "using the packaged C++ runtime"
  fi
  export BM_RESOURCE_DIR="$here/Resources"
  # The NVIDIA driver's OpenCL library, for the packaged ICD loader (a machine may list only other
  # vendors' ICDs, or none).
  local nv
  nv="$(ls /usr/local/nvidia/lib64/libnvidia-opencl.so.1 /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 \
    /usr/lib64/libnvidia-opencl.so.1 2>/dev/null | head -1)"
  [ -n "$nv" ] || nv="$(find / -xdev -name 'libnvidia-opencl.so*' 2>/dev/null | head -1)"
  if [ -n "$nv" ]; then
    # A vendors folder of its own: the loader reads it instead of /etc/OpenCL/vendors
    # (OCL_ICD_FILENAMES was not enough there: the platform did not appear).
    mkdir -p "$work/vendors"
    echo "$nv" >"$work/vendors/nvidia.icd"
    export OCL_ICD_VENDORS="$work/vendors"
    say "OpenCL ICD: $nv"
  else
    say "no libnvidia-opencl.so found"
  fi
  local threads
  threads="$(nproc)"
  local frames="${BM_GPU_FRAMES:-300}" warmup="${BM_GPU_WARMUP:-50}" secs="${BM_GPU_SESSION_S:-5}"
  local grid
  read -r -a grid <<<"${BM_GPU_GRID:-}"
  step() { # name, limit in s, command...
    local name="$1" limit="$2"
    shift 2
    case ",$steps," in *",$name,"*) ;; *) return 0 ;; esac
    local left=$((deadline - SECONDS - 15))
    [ "$limit" -le "$left" ] || limit=$left
    if [ "$limit" -lt 5 ]; then
      say "=== $name: skipped, no time left"
      return 0
    fi
    say "=== $name ($(date -u +%T), limit ${limit} s): $*"
    local t0=$SECONDS
    timeout --signal=INT --kill-after=10 "$limit" "$@" 2>&1 | tee -a "$log"
    local rc=${PIPESTATUS[0]}
    say "=== $name: exit $rc after $((SECONDS - t0)) s"
    pack
    return 0
  }
  {
    uname -a
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv
    lscpu | grep -E 'Model name|^CPU\(s\)|Thread|Socket'
    free -g | head -2
  } >"$res/machine.txt" 2>&1
  cat "$res/machine.txt" >>"$log"
  step devices 30 "$dir/bin/bmsim" devices
  "$dir/bin/bmsim" devices >"$res/devices.txt" 2>&1
  if ! grep -q '\[gpu\]' "$res/devices.txt"; then
    # Nothing to measure: say what the machine has, and stop before the benchmarks fall back to
    # the CPU backend.
    {
      echo "no OpenCL GPU device; the driver's libraries:"
      ls -l /usr/local/nvidia/lib64 /usr/lib/x86_64-linux-gnu 2>/dev/null | grep -iE 'nvidia|opencl|cuda' | head -40
      ls -l /etc/OpenCL/vendors 2>&1
    } | tee -a "$log"
    pack
    return 1
  fi
  step identity 120 "$dir/bin/BMOpenCLTests" --gtest_output=xml:"$res/identity.xml"
  if grep -q 'failures="[1-9]' "$res/identity.xml" 2>/dev/null; then
    # Which: the device compiler's optimisation (contraction into FMA, say) or the code.
    step identity 120 env BM_OPENCL_BUILD_OPTIONS=-cl-opt-disable "$dir/bin/BMOpenCLTests" \
      --gtest_filter='OpenCLIdentity.Lazar*:OpenCLSession.*' \
      --gtest_output=xml:"$res/identity-opt-disabled.xml"
  fi
  step grid-gpu 200 "$dir/bin/bmsim" bench --backends opencl --frames "$frames" --warmup "$warmup" \
    --cell-limit 60 "${grid[@]}" --out "$res/grid-gpu"
  step session 150 "$dir/bin/bmsim" bench --session glenoid --backends opencl --voxmaps 192,256 \
    --repeats 1 --seconds "$secs" --full-seconds 2 --out "$res/session-gpu"
  step session 60 "$dir/bin/bmsim" bench --session glenoid --backends cpu --voxmaps 192 \
    --repeats 1 --seconds "$secs" --full-seconds 2 --out "$res/session-cpu"
  # The work split on the GPU: lanes x groups against the shell 2048^3 x voxmap 1024^3 cell's p99
  # (and the launch floor at shell 128^3); the lazar grid again with the best.
  case ",$steps," in
  *",tune,"*)
    local best="" bestP99="" cfg
    for cfg in 128:4096 256:4096 64:4096 32:4096 128:1024 128:16384; do
      step tune 40 env BM_OPENCL_LANES="${cfg%%:*}" BM_OPENCL_GROUPS="${cfg##*:}" "$dir/bin/bmsim" \
        bench --backends opencl --methods lazar --shells 128,2048 --voxmaps 1024 \
        --frames "$frames" --warmup "$warmup" --out "$res/tune-${cfg%%:*}-${cfg##*:}"
      local p99
      p99="$(awk -F, '$3 == 2048 && $4 == 1024 && $5 == "ok" {print $10}' "$res/tune-${cfg%%:*}-${cfg##*:}/bench.csv" 2>/dev/null)"
      say "tune lanes:groups $cfg: p99 at 2048^3 x 1024^3 ${p99:-none} ms"
      if [ -n "$p99" ] && { [ -z "$bestP99" ] || awk -v a="$p99" -v b="$bestP99" 'BEGIN {exit !(a < b)}'; }; then
        best="$cfg"
        bestP99="$p99"
      fi
    done
    say "tune: best lanes:groups ${best:-none} (p99 ${bestP99:-none} ms)"
    if [ -n "$best" ]; then
      step tune 90 env BM_OPENCL_LANES="${best%%:*}" BM_OPENCL_GROUPS="${best##*:}" "$dir/bin/bmsim" \
        bench --backends opencl --methods lazar --frames "$frames" --warmup "$warmup" \
        --cell-limit 60 "${grid[@]}" --out "$res/grid-gpu-lazar"
    fi
    ;;
  esac
  step grid-cpu 200 "$dir/bin/bmsim" bench --backends cpu --threads "$threads" --frames "$frames" \
    --warmup "$warmup" --cell-limit 60 "${grid[@]}" --out "$res/grid-cpu"
  pack
  say "done"
}

case "${1:-}" in
package) package "${2:?package DIR}" ;;
run) run "${2:?run DIR OUT}" "${3:?run DIR OUT}" "${4:-}" ;;
*)
  echo "usage: $0 package DIR | run DIR OUT [STEPS]" >&2
  exit 2
  ;;
esac
