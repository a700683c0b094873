# TestBmsimTouch.cmake - `bmsim run --device touch` on a faulty Touch driver (the fake libHD of
# Testing/Logic/Session/FakeHD, its fault chosen by FAKEHD_FAULT): a driver that crashes while it
# loads, in hdInitDevice, when force output is enabled or in the servo callback, that hangs or is
# too old, is refused by name (exit 1, no signal, nothing written): bmsim tries the driver in a
# child process first. A driver that claims a nominal maximum of 10^6 N is sent at most the
# Touch's own 3.3 N (the fake logs the largest force it was sent).
#   cmake -DBMSIM=... -DFAKEHD=... -DWORK_DIR=... -P TestBmsimTouch.cmake
include(${CMAKE_CURRENT_LIST_DIR}/bmExpectRefused.cmake)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(cases
  "constructor|crashed during dlopen"
  "init|crashed during hdInitDevice"
  "hang|hung during hdInitDevice"
  "old-version|older than 3"
  "enable|crashed during hdEnable(HD_FORCE_OUTPUT)"
  "servo|crashed during the servo callback")
foreach(c IN LISTS cases)
  string(REPLACE "|" ";" parts "${c}")
  list(GET parts 0 fault)
  list(GET parts 1 needle)
  set(out "${WORK_DIR}/${fault}")
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env BM_LIBHD=${FAKEHD} FAKEHD_FAULT=${fault}
            ${BMSIM} run drilling --device touch --duration 0.5 --out ${out}
    RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr TIMEOUT 60)
  set(left "")
  if(EXISTS "${out}")
    file(GLOB left "${out}/*")
  endif()
  bm_check_refused("touch ${fault}" "${needle}" "${rc}" "${stdout}" "${stderr}" ${left})
endforeach()

# A driver claiming 10^6 N: the session runs against the fake, the device's limit is the Touch's
# 3.3 N (the summary says so) and no force above it reaches the driver.
set(log "${WORK_DIR}/forces.txt")
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env BM_LIBHD=${FAKEHD} FAKEHD_FAULT=huge-limit FAKEHD_FORCE_LOG=${log}
          ${BMSIM} run drilling --device touch --duration 0.5 --out ${WORK_DIR}/huge
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr TIMEOUT 60)
if(NOT (rc EQUAL 0 OR rc EQUAL 1))
  message(FATAL_ERROR "touch huge-limit: exit '${rc}'\n${stdout}${stderr}")
endif()
if(NOT EXISTS "${log}")
  message(FATAL_ERROR "touch huge-limit: the fake logged no forces\n${stdout}${stderr}")
endif()
file(READ "${log}" forces)
string(REGEX MATCH "^[^ ]+" worst "${forces}")
string(REGEX MATCH " ([0-9]+)" count "${forces}")
if(worst GREATER 3.3)
  message(FATAL_ERROR "touch huge-limit: ${worst} N was sent, more than the Touch's 3.3 N")
endif()
file(READ "${WORK_DIR}/huge/summary.json" summary)
string(JSON maxForce GET "${summary}" device_max_force_N)
if(NOT maxForce EQUAL 3.3)
  message(FATAL_ERROR "touch huge-limit: the device's limit is ${maxForce} N, not the Touch's 3.3")
endif()
message(STATUS "touch huge-limit: largest force sent ${worst} N (${forces}), limit ${maxForce} N")
