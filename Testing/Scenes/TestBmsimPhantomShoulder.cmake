# bmsim phantom shoulder, then bmsim import of it with an include seed on the glenoid plate and an
# exclude seed in the humeral head: the voxmap holds the plate only (its box ends before the joint
# space at x = -22 mm; analytic plate 38 400 mm^3, more at the threshold through the scanner's
# blur), while an import without the seeds keeps the two bones joined (the head reaches x = 22 mm).
# Also: the phantom names and ranges are refused with exit 2. Args: -DBMSIM= -DWORK_DIR=.
set(dir "${WORK_DIR}")
file(REMOVE_RECURSE "${dir}")
file(MAKE_DIRECTORY "${dir}")

execute_process(COMMAND "${BMSIM}" phantom shoulder --out "${dir}/ct" --quiet
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "bone volume: 83002\\.[0-9]+ mm\\^3")
  message(FATAL_ERROR "bmsim phantom shoulder (${rc}):\n${out}\n${err}")
endif()

# box_hi_x(<var> <import output>): the voxmap box's upper x, mm.
function(box_hi_x var text)
  if(NOT text MATCHES "voxmap: +[0-9]+ x [0-9]+ x [0-9]+ voxels of [0-9.]+ mm over \\[([-0-9.]+), ([-0-9.]+)\\]")
    message(FATAL_ERROR "no voxmap box in:\n${text}")
  endif()
  set(${var} "${CMAKE_MATCH_2}" PARENT_SCOPE)
endfunction()

execute_process(COMMAND "${BMSIM}" import "${dir}/ct" --out "${dir}/plate.nrrd" --quiet
                        --resolution 48 --seed -33.5,0,0 --exclude 0,0,0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS "${dir}/plate.nrrd")
  message(FATAL_ERROR "import with seeds (${rc}):\n${out}\n${err}")
endif()
box_hi_x(plate_hi "${out}")
if(NOT out MATCHES "bone volume: ([0-9.]+) mm\\^3")
  message(FATAL_ERROR "no bone volume in:\n${out}")
endif()
set(plate_volume "${CMAKE_MATCH_1}")
message(STATUS "seeded import: box up to x = ${plate_hi} mm, bone ${plate_volume} mm^3")
if(plate_hi GREATER -20 OR plate_volume LESS 30000 OR plate_volume GREATER 60000)
  message(FATAL_ERROR "the seeded import kept more than the glenoid plate:\n${out}")
endif()

execute_process(COMMAND "${BMSIM}" import "${dir}/ct" --out "${dir}/both.nrrd" --quiet
                        --resolution 48
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "import without seeds (${rc}):\n${out}\n${err}")
endif()
box_hi_x(both_hi "${out}")
message(STATUS "unseeded import: box up to x = ${both_hi} mm")
if(both_hi LESS 15)
  message(FATAL_ERROR "without seeds the humeral head should stay joined to the plate:\n${out}")
endif()

# Refusals: exit 2, the message naming the problem, nothing written.
foreach(case "femur;name the phantom" "shoulder;--noise: must be in \\[0, 1000\\]"
             "shoulder;--version applies to the scapula phantom only")
  list(GET case 0 name)
  list(GET case 1 expected)
  set(extra "")
  if(expected MATCHES "noise")
    set(extra --noise -1)
  elseif(expected MATCHES "version")
    set(extra --version 3)
  endif()
  execute_process(COMMAND "${BMSIM}" phantom ${name} --out "${dir}/refused" ${extra}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${expected}" OR EXISTS "${dir}/refused")
    message(FATAL_ERROR "phantom ${name} ${extra}: exit ${rc}, expected 2 and '${expected}':\n${err}")
  endif()
endforeach()
message(STATUS "bmsim phantom shoulder: passed")
