# BMPlanRun: the clinician's path on the scapula phantom, from the command line: `bmsim plan
# phantom` (DICOM written, glenoid found and measured, axis proposed), then `bmsim run plan.json`
# (the guide-pin hole, then the nipple-guided reamer on the same bone) at voxmap 96, checked for
# the plan summary's outcome; then the reaming step alone, without the pin hole, must stop at the
# nipple's contact with a message and exit 1. First a `bmsim plan phantom` stopped by SIGTERM
# after 3 s must leave no ct/ folder, and its temporaries must not block the run into the same
# folder, which removes them.
#   cmake -DBMSIM=... -DWORK_DIR=... -P TestPlanRun.cmake
foreach(v BMSIM WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "TestPlanRun.cmake needs -D${v}=")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/plan)
# A run stopped (SIGTERM) while it writes or imports the phantom's CT leaves only hidden
# temporaries in --out, no ct/ folder: the next run into the same folder is not blocked.
execute_process(COMMAND sh -c "'${BMSIM}' plan phantom --quiet --out '${WORK_DIR}/plan' >/dev/null 2>&1 &
                               pid=$!; sleep 3; kill -TERM $pid; wait $pid; echo $?"
                OUTPUT_VARIABLE stopped OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT stopped STREQUAL "143")
  message(FATAL_ERROR "bmsim plan phantom was not stopped while it worked (status ${stopped})")
endif()
file(GLOB visible RELATIVE ${WORK_DIR}/plan ${WORK_DIR}/plan/*)
list(FILTER visible EXCLUDE REGEX "^\\.") # the temporaries are hidden
if(visible)
  message(FATAL_ERROR "a stopped bmsim plan phantom left ${visible} in --out")
endif()

execute_process(COMMAND ${BMSIM} plan phantom --quiet --out ${WORK_DIR}/plan
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK_DIR}/plan/plan.json)
  message(FATAL_ERROR "bmsim plan phantom failed (${rc}):\n${out}\n${err}")
endif()
file(GLOB leftovers LIST_DIRECTORIES true ${WORK_DIR}/plan/.*)
if(leftovers)
  message(FATAL_ERROR "the stopped run's temporaries are still in --out: ${leftovers}")
endif()

execute_process(COMMAND ${BMSIM} run ${WORK_DIR}/plan/plan.json --voxmap-resolution 96 --no-report
                        --dicom --out ${WORK_DIR}/run
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bmsim run plan.json failed (${rc}):\n${out}\n${err}")
endif()
message(STATUS "${out}")
file(READ ${WORK_DIR}/run/summary.json summary)
string(JSON completed GET "${summary}" completed)
string(JSON nsteps LENGTH "${summary}" steps)
string(JSON angle GET "${summary}" outcome reamed_face_angle_to_axis_deg)
string(JSON seating GET "${summary}" outcome seating_fraction)
string(JSON medial GET "${summary}" outcome medialisation_mm)
string(JSON cortical GET "${summary}" outcome removed_cortical_mm3)
string(JSON cancellous GET "${summary}" outcome removed_cancellous_mm3)
string(JSON pinRemoved GET "${summary}" steps 0 summary removed_volume_mm3)
if(NOT completed STREQUAL "ON" OR NOT nsteps EQUAL 2)
  message(FATAL_ERROR "the plan did not complete both steps: completed ${completed}, ${nsteps} steps")
endif()
foreach(f 1-guide-pin/summary.json 1-guide-pin/forces.csv 2-ream/summary.json 2-ream/forces.csv)
  if(NOT EXISTS ${WORK_DIR}/run/${f})
    message(FATAL_ERROR "the plan run wrote no ${f}")
  endif()
endforeach()
# The results as DICOM beside the phantom's series (--dicom): a Segmentation and a Structured
# Report in its study, valid by dciodvfy (dicom3tools) where it is installed.
find_program(DCIODVFY dciodvfy)
foreach(f reamed-bone.seg.dcm plan.sr.dcm)
  if(NOT EXISTS ${WORK_DIR}/run/dicom/${f})
    message(FATAL_ERROR "bmsim run --dicom wrote no dicom/${f}")
  endif()
  if(DCIODVFY)
    execute_process(COMMAND ${DCIODVFY} ${WORK_DIR}/run/dicom/${f}
                    OUTPUT_VARIABLE vout ERROR_VARIABLE verr)
    if("${vout}${verr}" MATCHES "(^|\n)Error")
      message(FATAL_ERROR "dciodvfy finds errors in dicom/${f}:\n${vout}${verr}")
    endif()
  endif()
endforeach()
# --dicom on a scene that is not a plan, or on a plan whose CT is not a DICOM series: refused.
execute_process(COMMAND ${BMSIM} run drilling --dicom --out ${WORK_DIR}/not-a-plan
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--dicom: scene 'drilling' is not a plan")
  message(FATAL_ERROR "--dicom on a scene that is not a plan: exit ${rc}: ${err}")
endif()
file(READ ${WORK_DIR}/plan/plan.json plan)
string(JSON plan SET "${plan}" bone ct ct "\"${WORK_DIR}/plan/ct.nrrd\"")
file(WRITE ${WORK_DIR}/plan-nrrd.json "${plan}")
execute_process(COMMAND ${BMSIM} run ${WORK_DIR}/plan-nrrd.json --dicom --out ${WORK_DIR}/nrrd-run
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--dicom: the plan's CT '.*ct.nrrd' is not a DICOM series"
   OR EXISTS ${WORK_DIR}/nrrd-run/summary.json)
  message(FATAL_ERROR "--dicom on a plan whose CT is not a DICOM series: exit ${rc}: ${err}")
endif()

# Each step's summary and the plan's result name the coefficient set and whether it is calibrated
# (the reamer's default is the assumed, uncalibrated set).
string(JSON pinSet GET "${summary}" steps 0 summary coefficients name)
string(JSON pinCalibrated GET "${summary}" steps 0 summary coefficients calibrated)
string(JSON reamSet GET "${summary}" steps 1 summary coefficients name)
file(READ ${WORK_DIR}/run/plan_result.md result)
string(FIND "${result}" "${reamSet} (not calibrated)" reamAt)
if(pinSet STREQUAL "" OR reamSet STREQUAL "" OR reamAt EQUAL -1)
  message(FATAL_ERROR "the plan's summaries do not name the coefficient sets: pin '${pinSet}' "
                      "(calibrated ${pinCalibrated}), ream '${reamSet}'")
endif()
message(STATUS "coefficient sets: pin ${pinSet} (calibrated ${pinCalibrated}), ream ${reamSet}")
file(GLOB leftovers ${WORK_DIR}/run/.run.tmp-*)
if(leftovers)
  message(FATAL_ERROR "the plan run left its staging folder: ${leftovers}")
endif()
# The reamed face within 2 deg of the planned axis at this coarse voxmap (0.52 mm voxels), the
# joint line at the centre medialised by the 2 mm ream depth less the default reamer's face's rise
# at its centre above its foremost ring (1.33 mm): 0.67 mm, within 0.4 mm (most of a voxel), a
# 25 mm baseplate seated on bone, both tissues removed, and the pin's hole (radius 3.2 mm, 10 mm
# deep: ~280 mm^3 of bone).
if(angle GREATER 2.0 OR seating LESS 0.9 OR medial LESS 0.27 OR medial GREATER 1.07 OR
   cortical LESS 100 OR cancellous LESS 10 OR pinRemoved LESS 200 OR pinRemoved GREATER 360)
  message(FATAL_ERROR "plan outcome out of range: face ${angle} deg, seating ${seating}, "
                      "medialisation ${medial} mm, cortical ${cortical}, cancellous ${cancellous}, "
                      "pin ${pinRemoved} mm^3")
endif()

# Reaming without the guide-pin hole: the nipple meets solid bone; exit 1 and a message.
execute_process(COMMAND ${BMSIM} run ${WORK_DIR}/plan/step2-ream.json --voxmap-resolution 96
                        --no-report --out ${WORK_DIR}/ream-only
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err MATCHES "guide nipple .* met solid bone")
  message(FATAL_ERROR "reaming without the pin hole: exit ${rc}, expected 1 and the nipple's "
                      "message:\n${out}\n${err}")
endif()
message(STATUS "plan run: face ${angle} deg, seating ${seating}, medialisation ${medial} mm")
