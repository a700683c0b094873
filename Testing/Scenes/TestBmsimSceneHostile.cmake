# TestBmsimSceneHostile.cmake - `bmsim run` and `bmsim replay` on hostile scenes and recordings
# (Docs/Reliability.md, "Scenes and JSON", "Recordings"), run by ctest as
#   cmake -DBMSIM=<bmsim> -DWORK_DIR=<scratch folder> -P TestBmsimSceneHostile.cmake
# Each case is a small file written here; bmsim must exit 1 or 2 within the time bound, print a
# message naming the problem, and leave nothing in the output folder (nor above it: a scene named
# ../../x). The full corpus runs in the unit tests (TestHostileScene.cxx, TestHostileRecording.cxx).
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/bmExpectRefused.cmake)
foreach(var BMSIM WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "TestBmsimSceneHostile.cmake needs -D${var}=...")
  endif()
endforeach()
set(dir "${WORK_DIR}/hostile")
file(REMOVE_RECURSE "${dir}")
file(MAKE_DIRECTORY "${dir}/in" "${dir}/work/a/b")

function(expect_refusal name needle)
  execute_process(COMMAND "${BMSIM}" ${ARGN}
                  WORKING_DIRECTORY "${dir}/work/a/b"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr TIMEOUT 30)
  file(GLOB_RECURSE left "${dir}/work/*" "${dir}/x" "${dir}/x/*")
  bm_check_refused(${name} "${needle}" "${rc}" "${stdout}" "${stderr}" ${left})
endfunction()

function(scene name needle content)
  file(WRITE "${dir}/in/${name}" "${content}")
  expect_refusal("${name}" "${needle}" run "${dir}/in/${name}")
endfunction()

function(recording name needle content)
  file(WRITE "${dir}/in/${name}" "${content}")
  expect_refusal("${name}" "${needle}" replay "${dir}/in/${name}" --out "${dir}/work/replay")
endfunction()

string(REPEAT "[" 100000 open)
string(REPEAT "]" 100000 close)
scene(deep.json "nested deeper than 64 levels" "${open}${close}")
scene(deep-tool.json "nested deeper than 64 levels" "{\"tool\": ${open}${close}}")
scene(escape.json "must not start with '.'" "{\"name\": \"../../x\"}")
scene(slash.json "must not contain '/'" "{\"name\": \"a/../../../x\"}")
scene(lips.json "tool parameter 'lips' must be in [1, 64], got 10000"
  "{\"tool\": {\"type\": \"reamer\", \"lips\": 10000}}")
scene(material.json "material scale" "{\"bone\": {\"material\": -1}}")
scene(voxmap.json "voxmap resolution" "{\"voxmap_resolution\": 100000}")

set(columns "frame,time_s,device_x_mm,device_y_mm,device_z_mm,device_qw,device_qx,device_qy,device_qz,proxy_x_mm,proxy_y_mm,proxy_z_mm,feed_mm_per_rev,thrust_N,torque_Nmm,coupling_fx_N,coupling_fy_N,coupling_fz_N,device_fx_N,device_fy_N,device_fz_N,frame_ms,removed_voxels,removed_volume_mm3,speed_rpm,buttons,flags")
set(row "0,0,0,0,1,1,0,0,0,0,0,1,0.02,0,0,0,0,0,0,0,0,0.1,0,0,1000,0,0")
recording(deep.csv "nested deeper than 64 levels" "# bmsession {\"scene\": ${open}${close}}\n")
recording(sdf.csv "'sdf_resolution' must be in [8, 512], got 4096"
  "# bmsession {\"scene\": {}, \"session\": {\"sdf_resolution\": 4096}}\n${columns}\n${row}\n")
recording(empty.csv "no frames" "# bmsession {\"scene\": {}}\n${columns}\n")
recording(nan.csv "non-finite thrust"
  "# bmsession {\"scene\": {}}\n${columns}\n0,0,0,0,1,1,0,0,0,0,0,1,0.02,nan,0,0,0,0,0,0,0,0.1,0,0,1000,0,0\n")
find_program(MKFIFO mkfifo)
if(MKFIFO)
  execute_process(COMMAND "${MKFIFO}" "${dir}/in/fifo.csv")
  expect_refusal(fifo.csv "not a regular file" replay "${dir}/in/fifo.csv" --out "${dir}/work/replay")
endif()
