# BMPlanRealScan: the plan on a scan made the way a hospital's chest CT is (Docs/Planning.md, "Real
# scans"): the scapula phantom stored as an 8-bit display window (400 / 2000 HU) with 1.4 mm pixels
# and 2.5 mm slices (partial volume over each slice). From the command line:
#  - without an intensity option the plan is refused naming the options `plan` has;
#  - with the window's HU mapping, and with a raw threshold, the glenoid is found and measured
#    within 2 deg (version, inclination) and 2 mm (centre) of the truth, and the step scenes carry
#    the intensity setting: the guide-pin step runs on the 8-bit CT;
#  - --side left on this right shoulder finds no glenoid and says why;
#  - a centre and normal alone, on a region that leaves out the inferior angle, make a plan with the
#    measurements that need the scapular plane reported as not available;
#  - a normal placed into the bone is refused;
#  - with the humeral head 1 mm from the glenoid (joined at this resolution), a plan whose reamer
#    would start inside the head is refused with the reason.
#   cmake -DBMSIM=... -DWORK_DIR=... -P TestPlanRealScan.cmake
include(${CMAKE_CURRENT_LIST_DIR}/bmPlanChecks.cmake)
plan_test_setup(TestPlanRealScan.cmake)


run("${BMSIM}" phantom scapula --window 400,2000 --pixel-mm 1.4 --slice-mm 2.5 --quiet
    --out "${dir}/scan")
if(NOT rc EQUAL 0 OR NOT EXISTS "${dir}/scan/ct.nrrd")
  message(FATAL_ERROR "phantom scapula --window (${rc}):\n${out}\n${err}")
endif()
if(NOT out MATCHES "--hu-mapping ([-0-9.]+),([-0-9.]+)")
  message(FATAL_ERROR "the phantom does not say how to read its window:\n${out}")
endif()
set(mapping "${CMAKE_MATCH_1},${CMAKE_MATCH_2}")
file(READ "${dir}/scan/truth.json" truth)
foreach(a 0 1 2)
  string(JSON t_c${a} GET "${truth}" glenoid_centre_mm ${a})
  string(JSON t_n${a} GET "${truth}" face_normal ${a})
endforeach()

# 1. No intensity option: refused, naming options that `plan` has.
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --out "${dir}/p0")
if(NOT rc EQUAL 1 OR NOT err MATCHES "--raw-threshold" OR EXISTS "${dir}/p0/plan.json")
  message(FATAL_ERROR "an 8-bit CT without an intensity option: exit ${rc}:\n${out}\n${err}")
endif()
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --raw-threshold 102 --out "${dir}/p0b")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plan --raw-threshold (${rc}):\n${out}\n${err}")
endif()
file(READ "${dir}/p0b/plan_report.md" report)
if(NOT report MATCHES "as stored, not HU" OR report MATCHES "HU range")
  message(FATAL_ERROR "the raw-value plan's report speaks of HU:\n${report}")
endif()
file(READ "${dir}/p0b/step1-guide-pin.json" pin)
string(JSON raw ERROR_VARIABLE e GET "${pin}" bone ct rawThreshold)
if(NOT raw EQUAL 102)
  message(FATAL_ERROR "the guide-pin step does not read the CT with the raw threshold:\n${pin}")
endif()

# 2. The window's mapping: measured against the truth.
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --hu-mapping ${mapping} --out "${dir}/p1")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plan --hu-mapping ${mapping} (${rc}):\n${out}\n${err}")
endif()
message(STATUS "${out}")
check_plan("${dir}/p1/plan.json" "${dir}/scan/truth.json" 2 2 "8-bit, 2.5 mm slices")
# The guide-pin step reads the 8-bit CT through the plan's mapping.
run("${BMSIM}" run "${dir}/p1/step1-guide-pin.json" --voxmap-resolution 64 --no-report
    --out "${dir}/pin")
if(NOT rc EQUAL 0 OR NOT EXISTS "${dir}/pin/summary.json")
  message(FATAL_ERROR "the guide-pin step on the 8-bit CT (${rc}):\n${out}\n${err}")
endif()
file(READ "${dir}/pin/summary.json" summary)
string(JSON removed GET "${summary}" removed_volume_mm3)
if(removed LESS 50)
  message(FATAL_ERROR "the guide-pin step removed ${removed} mm^3 (expected its hole)")
endif()

# A seed for the steps' bone that is not on the glenoid's scapula: refused, nothing left.
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --hu-mapping ${mapping} --seed 0,0,0
    --out "${dir}/pseed")
if(NOT rc EQUAL 2 OR NOT err MATCHES "--seed .* not on bone" OR EXISTS "${dir}/pseed")
  message(FATAL_ERROR "a seed off the scapula: exit ${rc}:\n${out}\n${err}")
endif()

# 3. The other side: no glenoid, and why.
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --hu-mapping ${mapping} --side left
    --out "${dir}/p2")
if(NOT rc EQUAL 3 OR NOT err MATCHES "faces the patient's right" OR EXISTS "${dir}/p2/plan.json")
  message(FATAL_ERROR "--side left on a right shoulder: exit ${rc}:\n${out}\n${err}")
endif()

# 4. A centre and normal alone, the region ending 45 mm below the centre: a plan, uncorrected,
# with the scapular plane's measurements not available.
string(REGEX REPLACE "\\..*" "" cz "${t_c2}")
math(EXPR zlo "${cz} - 45")
math(EXPR zhi "${cz} + 200")
file(WRITE "${dir}/placed.json"
     "{\"glenoid_centre_mm\": [${t_c0}, ${t_c1}, ${t_c2}], \"face_normal\": [${t_n0}, ${t_n1}, ${t_n2}]}")
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --hu-mapping ${mapping} --landmarks
    "${dir}/placed.json" --roi=-400,-400,${zlo},400,400,${zhi} --out "${dir}/p3")
if(NOT rc EQUAL 0 OR NOT out MATCHES "not available: inclination_deg" OR
   NOT out MATCHES "the face normal, not corrected" OR NOT EXISTS "${dir}/p3/step2-ream.json")
  message(FATAL_ERROR "a centre and normal alone (${rc}):\n${out}\n${err}")
endif()
file(READ "${dir}/p3/plan_report.md" report)
if(NOT report MATCHES "not available" OR report MATCHES "nan")
  message(FATAL_ERROR "the manual plan's report:\n${report}")
endif()

# 5. The normal placed the wrong way round.
foreach(a 0 1 2)
  string(REGEX REPLACE "^-" "" nabs "${t_n${a}}")
  if(t_n${a} MATCHES "^-")
    set(rn${a} "${nabs}")
  else()
    set(rn${a} "-${t_n${a}}")
  endif()
endforeach()
file(WRITE "${dir}/reversed.json"
     "{\"glenoid_centre_mm\": [${t_c0}, ${t_c1}, ${t_c2}], \"face_normal\": [${rn0}, ${rn1}, ${rn2}]}")
run("${BMSIM}" plan "${dir}/scan/ct.nrrd" --quiet --hu-mapping ${mapping} --landmarks
    "${dir}/reversed.json" --out "${dir}/p4")
if(NOT rc EQUAL 3 OR NOT err MATCHES "points into the bone" OR EXISTS "${dir}/p4/plan.json")
  message(FATAL_ERROR "a normal into the bone: exit ${rc}:\n${out}\n${err}")
endif()

# 6. The humeral head 1 mm from the glenoid (no joint space at 1.4 mm pixels and 2.5 mm slices):
# placed by hand, the reamer would start inside the head; refused with the reason (exit 3), no
# plan written.
run("${BMSIM}" phantom scapula --joint-gap 1 --window 400,2000 --pixel-mm 1.4 --slice-mm 2.5
    --quiet --out "${dir}/fused")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "phantom scapula --joint-gap 1 (${rc}):\n${out}\n${err}")
endif()
# Joined, the joint space is filled as a cavity: the placed centre is then buried (refused,
# naming the fill); without filling, the reamer's path is the head.
run("${BMSIM}" plan "${dir}/fused/ct.nrrd" --quiet --hu-mapping ${mapping} --landmarks
    "${dir}/placed.json" --out "${dir}/p5a")
if(NOT rc EQUAL 3 OR NOT err MATCHES "without filling holes")
  message(FATAL_ERROR "a centre buried by the filled joint space: exit ${rc}:\n${out}\n${err}")
endif()
run("${BMSIM}" plan "${dir}/fused/ct.nrrd" --quiet --hu-mapping ${mapping} --landmarks
    "${dir}/placed.json" --no-fill-holes --out "${dir}/p5")
if(NOT rc EQUAL 3 OR NOT err MATCHES "start inside bone" OR EXISTS "${dir}/p5/plan.json")
  message(FATAL_ERROR "a reamer starting inside the humeral head: exit ${rc}:\n${out}\n${err}")
endif()
message(STATUS "bmsim plan on an 8-bit 2.5 mm scan: passed")
