# BMPlanScanMatrix: the plan on scans made as scanners and patients make them (Docs/Planning.md,
# "Real scans"), each from `bmsim phantom scapula` and planned by `bmsim plan` with its truth:
#  - the patient turned 15 deg either way about the scanner's axis (8-bit window, 1.4 mm pixels,
#    2.5 mm slices): 3D version and inclination within 2 deg, the glenoid centre within 2 mm;
#  - a scapula with its spine, the patient tilted 20 deg about the left-right axis either way and
#    about the front-back axis (the trigonum found at the spine's root, in the scapula's own
#    frame): the same limits;
#  - the humeral head joined to the glenoid at the threshold (a 1 mm joint space, a ball or a
#    proximal humerus on a turned patient; and a scapula with its spine tilted 20 deg about the
#    front-back axis): cut off along its sphere, the same limits; the joined humerus plan's steps
#    run on a bone that leaves the head out (no tool starting in bone, no guide meeting bone
#    before the face);
#  - osteoporotic bone (cancellous at 100 HU, below the threshold): the humeral head a shell;
#  - the arm raised above the head (the scapula turned 30 deg upward, the humeral shaft up);
#  - the volume stored along permuted and reversed axes with the direction cosines that say so;
#  - a left shoulder and a B2 (posteriorly worn) glenoid on the same scan;
#  - both shoulders in one DICOM series: with no side the plan stops naming both; each side
#    planned within 2 deg / 2 mm of its own truth;
#  - 0.6 mm pixels and 1 mm slices (HU), a scapula with its spine: within 1 deg and 1 mm, the
#    clinical target.
#   cmake -DBMSIM=... -DWORK_DIR=... -P TestPlanScanMatrix.cmake
include(${CMAKE_CURRENT_LIST_DIR}/bmPlanChecks.cmake)
plan_test_setup(TestPlanScanMatrix.cmake)

# plan_case(NAME DEG MM PHANTOM_ARGS... [PLAN ARGS...]): phantom, plan with the window's mapping,
# check against truth.json.
set(coarse --window 400,2000 --pixel-mm 1.4 --slice-mm 2.5)
function(plan_case name deg mm)
  cmake_parse_arguments(C "" "" "PHANTOM;PLAN" ${ARGN})
  file(MAKE_DIRECTORY "${dir}/${name}")
  run("${BMSIM}" phantom scapula ${C_PHANTOM} --quiet --out "${dir}/${name}/scan")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: phantom scapula ${C_PHANTOM} (${rc}):\n${out}\n${err}")
  endif()
  set(ct "${dir}/${name}/scan")
  set(mapping "")
  if(out MATCHES "--hu-mapping ([-0-9.]+),([-0-9.]+)")
    set(ct "${ct}/ct.nrrd")
    set(mapping --hu-mapping "${CMAKE_MATCH_1},${CMAKE_MATCH_2}")
  endif()
  run("${BMSIM}" plan "${ct}" --quiet ${mapping} ${C_PLAN} --out "${dir}/${name}/plan")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: plan (${rc}):\n${out}\n${err}")
  endif()
  check_plan("${dir}/${name}/plan/plan.json" "${dir}/${name}/scan/truth.json" ${deg} ${mm}
             "${name}")
endfunction()

foreach(r "0,0,15" "0,0,-15")
  string(REPLACE "," "_" tag "${r}")
  string(REPLACE "-" "m" tag "${tag}")
  plan_case(rotated_${tag} 2 2 PHANTOM ${coarse} --rotate=${r})
endforeach()
foreach(r "20,0,0" "-20,0,0" "0,-20,0")
  string(REPLACE "," "_" tag "${r}")
  string(REPLACE "-" "m" tag "${tag}")
  plan_case(tilted_${tag} 2 2 PHANTOM ${coarse} --spine --rotate=${r})
endforeach()
plan_case(joined 2 2 PHANTOM ${coarse} --joint-gap 1)
plan_case(joined_humerus 2 2 PHANTOM ${coarse} --joint-gap 1 --humerus --spine --rotate=10,0,-10)
plan_case(tilted_0_20_0 2 2 PHANTOM ${coarse} --spine --rotate=0,20,0)
plan_case(osteoporotic 2 2 PHANTOM ${coarse} --cancellous-hu 100 --spine)
plan_case(arm_raised 2 2 PHANTOM ${coarse} --arm-raised --spine)
# Stored with the slices' axis first and superior at low indices, rows along x, columns along y.
plan_case(stored_axes 2 2 PHANTOM ${coarse} --spine --axes=-z,x,y)
run("${BMSIM}" phantom scapula ${coarse} --axes x,x,y --out "${dir}/bad-axes")
if(NOT rc EQUAL 2 OR NOT err MATCHES "--axes: stored axes 'x,x,y'" OR EXISTS "${dir}/bad-axes")
  message(FATAL_ERROR "--axes x,x,y (${rc}):\n${out}\n${err}")
endif()
foreach(name joined joined_humerus tilted_0_20_0)
  file(READ "${dir}/${name}/plan/plan_report.md" report)
  file(READ "${dir}/${name}/plan/step2-ream.json" ream)
  if(NOT report MATCHES "cut off along its sphere" OR NOT ream MATCHES "exclude_heads")
    message(FATAL_ERROR "${name}: the joined head was not cut off, or its steps keep it")
  endif()
endforeach()
run("${BMSIM}" run "${dir}/joined_humerus/plan/plan.json" --out "${dir}/joined_humerus/run")
if(NOT rc EQUAL 0 OR "${out}${err}" MATCHES "starts inside bone|met solid bone")
  message(FATAL_ERROR "joined_humerus: the plan's steps (${rc}):\n${out}\n${err}")
endif()
plan_case(left 2 2 PHANTOM ${coarse} --left)
plan_case(b2 2 2 PHANTOM ${coarse} --b2)
plan_case(fine 1 1 PHANTOM --pixel-mm 0.6 --slice-mm 1 --spine)

# Both shoulders in one series (HU, 1.4 mm pixels, 2.5 mm slices).
run("${BMSIM}" phantom scapula --both --pixel-mm 1.4 --slice-mm 2.5 --quiet --out "${dir}/both")
if(NOT rc EQUAL 0 OR NOT EXISTS "${dir}/both/truth_left.json")
  message(FATAL_ERROR "phantom scapula --both (${rc}):\n${out}\n${err}")
endif()
run("${BMSIM}" plan "${dir}/both" --quiet --out "${dir}/both-auto")
if(NOT rc EQUAL 3 OR NOT err MATCHES "both shoulders are in the scan.*--side" OR
   EXISTS "${dir}/both-auto/plan.json")
  message(FATAL_ERROR "both shoulders, no side: exit ${rc}:\n${out}\n${err}")
endif()
foreach(side right left)
  run("${BMSIM}" plan "${dir}/both" --quiet --side ${side} --out "${dir}/both-${side}")
  if(NOT rc EQUAL 0 OR NOT out MATCHES "${side} shoulder")
    message(FATAL_ERROR "both shoulders, --side ${side} (${rc}):\n${out}\n${err}")
  endif()
endforeach()
check_plan("${dir}/both-right/plan.json" "${dir}/both/truth.json" 2 2 "both shoulders, right")
check_plan("${dir}/both-left/plan.json" "${dir}/both/truth_left.json" 2 2 "both shoulders, left")
message(STATUS "bmsim plan over the scan matrix: passed")
