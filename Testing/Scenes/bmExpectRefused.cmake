# bmExpectRefused.cmake - the check the hostile-input scripts (TestBmsim*Hostile.cmake) make of
# each refused bmsim run: exit 1 or 2, a message on stderr that names the problem, nothing left.
#   bm_check_refused(NAME NEEDLE RC STDOUT STDERR [LEFT_FILES...])
# LEFT_FILES: what the caller found in the places the run must not have written.
function(bm_check_refused name needle rc stdout stderr)
  if(NOT (rc EQUAL 1 OR rc EQUAL 2))
    message(FATAL_ERROR "${name}: exit '${rc}', expected 1 or 2\n${stdout}${stderr}")
  endif()
  string(FIND "${stderr}" "${needle}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${name}: the message does not say '${needle}':\n${stderr}")
  endif()
  if(ARGN)
    message(FATAL_ERROR "${name}: left ${ARGN}")
  endif()
  message(STATUS "${name}: exit ${rc}: ${stderr}")
endfunction()
