# TestBmsimBenchSessionAccuracy.cmake - `bmsim bench --session glenoid --accuracy`, run by ctest as
#   cmake -DBMSIM=<bmsim> -DWORK_DIR=<scratch folder> [-DCHART=ON] -P TestBmsimBenchSessionAccuracy.cmake
# Checks (not timed): the session bench at voxmaps 32 and 48 then the offline reaming trial at
# each and at the reference 64; session_accuracy.csv has a row per voxmap, the reference's with
# zero errors and no frame time, the others with their frame p99 and errors within what their
# voxels allow (removed volume within 15 %, the face's depth within a voxel, its orientation
# within 3 deg); the chart is written (CHART); a drilling scene is refused before it runs.
cmake_minimum_required(VERSION 3.20)
foreach(var BMSIM WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "TestBmsimBenchSessionAccuracy.cmake needs -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
set(args bench --session glenoid --voxmaps 32,48 --seconds 0.3 --repeats 1 --accuracy 64
    --out "${WORK_DIR}")
execute_process(COMMAND "${BMSIM}" ${args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
message(STATUS "bmsim ${args}: exit ${rc}\n${stdout}${stderr}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bmsim bench --session --accuracy failed (${rc})")
endif()
file(STRINGS "${WORK_DIR}/session_accuracy.csv" lines)
list(LENGTH lines count)
if(NOT count EQUAL 4)
  message(FATAL_ERROR "session_accuracy.csv has ${count} lines, expected a header and 3 rows")
endif()
list(GET lines 0 header)
string(REPLACE "," ";" columns "${header}")
foreach(name voxmap voxel_mm p99_ms removed_mm3 removed_error_pct face_depth_error_mm
             face_error_deg reference_voxmap)
  list(FIND columns ${name} i_${name})
  if(i_${name} LESS 0)
    message(FATAL_ERROR "session_accuracy.csv has no column ${name}: ${header}")
  endif()
endforeach()
set(seen "")
foreach(i 1 2 3)
  list(GET lines ${i} line)
  string(REPLACE "," ";" f "${line}")
  foreach(name voxmap voxel_mm p99_ms removed_mm3 removed_error_pct face_depth_error_mm
               face_error_deg reference_voxmap)
    list(GET f ${i_${name}} ${name})
  endforeach()
  list(APPEND seen ${voxmap})
  if(NOT reference_voxmap EQUAL 64 OR NOT removed_mm3 GREATER 500)
    message(FATAL_ERROR "row ${line}: reference ${reference_voxmap}, removed ${removed_mm3} mm^3")
  endif()
  # |errors| as text without the sign, compared as numbers.
  string(REGEX REPLACE "^-" "" removed_abs "${removed_error_pct}")
  string(REGEX REPLACE "^-" "" depth_abs "${face_depth_error_mm}")
  if(voxmap EQUAL 64)
    if(NOT removed_error_pct EQUAL 0 OR NOT face_error_deg EQUAL 0 OR NOT p99_ms EQUAL 0)
      message(FATAL_ERROR "the reference's row has errors or a frame time: ${line}")
    endif()
  elseif(NOT p99_ms GREATER 0 OR removed_abs GREATER 15 OR depth_abs GREATER voxel_mm OR
         face_error_deg GREATER 3)
    message(FATAL_ERROR "voxmap ${voxmap}: p99 ${p99_ms} ms, removed ${removed_error_pct} %, "
                        "depth ${face_depth_error_mm} mm (voxel ${voxel_mm}), face "
                        "${face_error_deg} deg: ${line}")
  endif()
endforeach()
if(NOT seen STREQUAL "32;48;64")
  message(FATAL_ERROR "session_accuracy.csv rows are voxmaps ${seen}, expected 32;48;64")
endif()
if(CHART AND NOT EXISTS "${WORK_DIR}/session_speed_vs_accuracy.png")
  message(FATAL_ERROR "no session_speed_vs_accuracy.png")
endif()
execute_process(COMMAND "${BMSIM}" bench --session drilling --accuracy 64 --out "${WORK_DIR}/drill"
                RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 2 OR NOT "${stderr}" MATCHES "--accuracy: scene 'drilling' cuts with a drill"
   OR EXISTS "${WORK_DIR}/drill/session.csv")
  message(FATAL_ERROR "a drilling scene's --accuracy: exit ${rc}\n${stdout}${stderr}")
endif()
