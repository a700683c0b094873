# TestBmsimRun.cmake - `bmsim run` from the command line, run by ctest as
#   cmake -DBMSIM=<bmsim> -DWORK_DIR=<scratch folder> -DMODE=<mode> -P TestBmsimRun.cmake
# MODE:
#   outputs  drilling at shell 512 / voxmap 128 writes forces.csv and summary.json with the
#            documented keys, thrust 5-30 N and torque 10-50 N mm (Lee et al.'s ranges)
#            then a session run into the same folder leaves its session.csv and summary.json,
#            not the feed trial's forces.csv beside them (another run's outputs are removed)
#   threads  --threads 1 and --threads 2 give identical thrust, torque and removed voxels
#   zheng    --method zheng runs through the same command and reports positive forces
#   badargs  bad arguments exit non-zero with a message and leave no output folder
#   killed   a run killed (SIGKILL) while it works leaves the output folder as it was (an earlier
#            run's set untouched, no new file; only its hidden staging folder), and the next run
#            into that folder removes the staging folder and writes a complete set
#   session  haptic sessions on scenes that are not blocks, at small resolutions: the glenoid
#            phantom in force mode at the default force scale runs, records, and `bmsim replay`
#            rebuilds its bone and reproduces the forces; the skull CT (when Debian's
#            invesalius-examples is installed) is cut by the scripted hand and replayed; --force
#            above the Touch's 3.3 N, an unwritable --record and a broken recording are refused,
#            leaving no output
cmake_minimum_required(VERSION 3.20)
foreach(var BMSIM WORK_DIR MODE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "TestBmsimRun.cmake needs -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}/${MODE}")
file(MAKE_DIRECTORY "${WORK_DIR}/${MODE}")
set(dir "${WORK_DIR}/${MODE}")

# bmsim_run(<out folder> <args...>): runs `bmsim run drilling --out <folder> args`, must succeed.
function(bmsim_run out)
  execute_process(COMMAND "${BMSIM}" run drilling --no-report --out "${out}" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  string(REPLACE ";" " " args "${ARGN}")
  message(STATUS "bmsim run drilling ${args}: exit ${rc}\n${stdout}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bmsim run drilling ${args} failed (${rc}):\n${stderr}")
  endif()
endfunction()

# summary_get(<var> <folder> <key>): a value of <folder>/summary.json.
function(summary_get var out key)
  file(READ "${out}/summary.json" json)
  string(JSON value ERROR_VARIABLE err GET "${json}" "${key}")
  if(err)
    message(FATAL_ERROR "${out}/summary.json: no key '${key}' (${err})")
  endif()
  set(${var} "${value}" PARENT_SCOPE)
endfunction()

function(expect_range name value lo hi)
  if(NOT (value GREATER lo AND value LESS hi))
    message(FATAL_ERROR "${name} = ${value}, expected in (${lo}, ${hi})")
  endif()
  message(STATUS "${name} = ${value} (expected in (${lo}, ${hi}))")
endfunction()

set(low --shell-resolution 512 --voxmap-resolution 128)

if(MODE STREQUAL "outputs")
  bmsim_run("${dir}/out" ${low})
  foreach(f forces.csv summary.json)
    if(NOT EXISTS "${dir}/out/${f}")
      message(FATAL_ERROR "bmsim run wrote no ${f}")
    endif()
  endforeach()
  file(STRINGS "${dir}/out/forces.csv" lines)
  list(LENGTH lines nlines)
  list(GET lines 0 header)
  if(NOT header STREQUAL "time_s,depth_mm,feed_mm_per_rev,thrust_N,torque_Nmm,frame_ms,removed_voxels")
    message(FATAL_ERROR "forces.csv header: ${header}")
  endif()
  if(nlines LESS 1000)
    message(FATAL_ERROR "forces.csv has ${nlines} lines, expected one per frame (> 1000)")
  endif()
  foreach(key thrust_N torque_Nmm thrust_ripple reference_thrust_N reference_torque_Nmm frame_ms_p50
              frame_ms_p99 removed_volume_mm3 voxmap_resolution shell_resolution method threads)
    summary_get(v "${dir}/out" ${key})
    message(STATUS "summary ${key} = ${v}")
    set(s_${key} "${v}")
  endforeach()
  expect_range(thrust_N "${s_thrust_N}" 5 30)
  expect_range(torque_Nmm "${s_torque_Nmm}" 10 50)
  expect_range(reference_thrust_N "${s_reference_thrust_N}" 5 30)
  expect_range(thrust_ripple "${s_thrust_ripple}" -1e-12 0.05)
  expect_range(removed_volume_mm3 "${s_removed_volume_mm3}" 1 10)
  if(NOT s_voxmap_resolution EQUAL 128 OR NOT s_shell_resolution EQUAL 512 OR NOT s_method STREQUAL "lazar"
     OR NOT s_threads EQUAL 2)
    message(FATAL_ERROR "summary does not echo the run's settings: voxmap ${s_voxmap_resolution}, shell "
                        "${s_shell_resolution}, method ${s_method}, threads ${s_threads}")
  endif()
  # The drilling scene's forces come from the calibrated default drilling set, and it says so.
  file(READ "${dir}/out/summary.json" text)
  string(JSON set_name GET "${text}" coefficients name)
  string(JSON set_calibrated GET "${text}" coefficients calibrated)
  if(NOT set_name STREQUAL "drilling-bovine-orelaja2020" OR NOT set_calibrated STREQUAL "ON")
    message(FATAL_ERROR "summary coefficients: ${set_name}, calibrated ${set_calibrated}")
  endif()
  if(NOT s_frame_ms_p99 GREATER_EQUAL s_frame_ms_p50 OR NOT s_frame_ms_p50 GREATER 0)
    message(FATAL_ERROR "frame times: p50 ${s_frame_ms_p50}, p99 ${s_frame_ms_p99}")
  endif()
  # Re-running into the same folder replaces the outputs (atomic saves over existing files).
  bmsim_run("${dir}/out" --shell-resolution 128 --voxmap-resolution 32)
  summary_get(v "${dir}/out" shell_resolution)
  if(NOT v EQUAL 128)
    message(FATAL_ERROR "second run did not replace summary.json")
  endif()
  file(GLOB leftovers "${dir}/out/.*")
  list(FILTER leftovers EXCLUDE REGEX "/\\.bmsim-outputs$") # the list of the run's outputs
  if(leftovers)
    message(FATAL_ERROR "temporary files left behind: ${leftovers}")
  endif()

  bmsim_run("${dir}/mixed" ${low})
  # A run of another kind into the same folder: only its own outputs remain (and a user's file).
  file(WRITE "${dir}/mixed/notes.txt" "mine\n")
  bmsim_run("${dir}/mixed" ${low} --device scripted --duration 0.05)
  if(EXISTS "${dir}/mixed/forces.csv" OR NOT EXISTS "${dir}/mixed/session.csv"
     OR NOT EXISTS "${dir}/mixed/notes.txt")
    file(GLOB left "${dir}/mixed/*")
    message(FATAL_ERROR "a session run into a feed trial's folder left: ${left}")
  endif()
elseif(MODE STREQUAL "threads")
  foreach(t 1 2)
    bmsim_run("${dir}/t${t}" ${low} --threads ${t})
    foreach(key thrust_N torque_Nmm removed_voxels removed_volume_mm3 threads)
      summary_get(${key}_${t} "${dir}/t${t}" ${key})
    endforeach()
  endforeach()
  if(NOT threads_1 EQUAL 1 OR NOT threads_2 EQUAL 2)
    message(FATAL_ERROR "summary threads: ${threads_1}, ${threads_2}")
  endif()
  foreach(key thrust_N torque_Nmm removed_voxels removed_volume_mm3)
    message(STATUS "${key}: 1 thread ${${key}_1}, 2 threads ${${key}_2}")
    if(NOT "${${key}_1}" STREQUAL "${${key}_2}")
      message(FATAL_ERROR "${key} differs between 1 and 2 threads: ${${key}_1} vs ${${key}_2}")
    endif()
  endforeach()

elseif(MODE STREQUAL "zheng")
  bmsim_run("${dir}/out" --method zheng --shell-resolution 256 --voxmap-resolution 64)
  summary_get(method "${dir}/out" method)
  summary_get(engine "${dir}/out" engine)
  summary_get(thrust "${dir}/out" thrust_N)
  summary_get(torque "${dir}/out" torque_Nmm)
  summary_get(ref "${dir}/out" reference_thrust_N)
  if(NOT method STREQUAL "zheng")
    message(FATAL_ERROR "summary method ${method}, engine ${engine}")
  endif()
  expect_range(zheng_thrust_N "${thrust}" 5 30)
  expect_range(zheng_torque_Nmm "${torque}" 10 50)
  expect_range(zheng_reference_thrust_N "${ref}" 5 30)

elseif(MODE STREQUAL "killed")
  bmsim_run("${dir}/out" --voxmap-resolution 64 --shell-resolution 128)
  file(SHA256 "${dir}/out/forces.csv" forcesBefore)
  file(SHA256 "${dir}/out/summary.json" summaryBefore)
  # A long run into the same folder, killed after 2 s (the trial takes tens of seconds).
  execute_process(COMMAND sh -c "\"${BMSIM}\" run drilling --no-report --out \"${dir}/out\" \
                                 --voxmap-resolution 256 --shell-resolution 1024 >/dev/null 2>&1 &
                                 pid=$!; sleep 2; kill -9 $pid; wait $pid; echo $?"
                  OUTPUT_VARIABLE killed OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT killed STREQUAL "137")
    message(FATAL_ERROR "the long run was not killed while it worked (status ${killed})")
  endif()
  file(SHA256 "${dir}/out/forces.csv" forcesAfter)
  file(SHA256 "${dir}/out/summary.json" summaryAfter)
  if(NOT forcesAfter STREQUAL forcesBefore OR NOT summaryAfter STREQUAL summaryBefore)
    message(FATAL_ERROR "a killed run changed the earlier run's outputs")
  endif()
  file(GLOB staged LIST_DIRECTORIES true "${dir}/out/.run.tmp-*")
  list(LENGTH staged nStaged)
  file(GLOB visible RELATIVE "${dir}/out" "${dir}/out/*")
  list(FILTER visible EXCLUDE REGEX "^\\.bmsim-outputs$") # the earlier run's list of outputs
  message(STATUS "after the kill: ${visible}; staging folders: ${nStaged}")
  if(NOT visible STREQUAL "forces.csv;summary.json" OR nStaged GREATER 1)
    message(FATAL_ERROR "a killed run left ${visible} and ${nStaged} staging folders")
  endif()
  bmsim_run("${dir}/out" --voxmap-resolution 64 --shell-resolution 128 --feed 0.03)
  file(GLOB staged LIST_DIRECTORIES true "${dir}/out/.run.tmp-*")
  file(SHA256 "${dir}/out/summary.json" summaryNext)
  if(staged OR summaryNext STREQUAL summaryBefore)
    message(FATAL_ERROR "the next run did not clean the staging folder (${staged}) or did not "
                        "write its own summary")
  endif()
elseif(MODE STREQUAL "badargs")
  file(WRITE "${dir}/malformed.json" "{ \"name\": \"broken\", \"voxmap_resolution\": ")
  file(WRITE "${dir}/badfield.json" "{ \"name\": \"broken\", \"voxmap_resolutoin\": 64 }")
  set(cases
      "unknown option|--bogus|1"
      "non-numeric feed|--feed|abc"
      "voxmap resolution 3|--voxmap-resolution|3"
      "threads 0|--threads|0"
      "bad method|--method|vps"
      "unknown scene|@scene@|no-such-scene"
      "malformed scene file|@scene@|${dir}/malformed.json"
      "scene file with an unknown field|@scene@|${dir}/badfield.json"
      "missing scene file|@scene@|${dir}/missing.json")
  set(i 0)
  foreach(c IN LISTS cases)
    string(REPLACE "|" ";" parts "${c}")
    list(GET parts 0 what)
    list(GET parts 1 opt)
    list(GET parts 2 value)
    math(EXPR i "${i} + 1")
    set(out "${dir}/out${i}")
    if(opt STREQUAL "@scene@")
      set(args run "${value}" --out "${out}" --shell-resolution 64 --voxmap-resolution 32)
    else()
      set(args run drilling --out "${out}" --shell-resolution 64 --voxmap-resolution 32 ${opt} ${value})
    endif()
    execute_process(COMMAND "${BMSIM}" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
    string(STRIP "${stderr}" stderr)
    message(STATUS "${what}: exit ${rc}: ${stderr}")
    if(rc EQUAL 0)
      message(FATAL_ERROR "${what}: bmsim ${args} succeeded, expected a failure")
    endif()
    if(NOT stderr MATCHES "bmsim run")
      message(FATAL_ERROR "${what}: no message on stderr (got '${stderr}')")
    endif()
    if(EXISTS "${out}")
      message(FATAL_ERROR "${what}: left an output folder ${out}")
    endif()
  endforeach()

elseif(MODE STREQUAL "session")
  set(small --voxmap-resolution 40 --shell-resolution 72)
  # expect_refused(<what> <pattern> <out folder> <args...>): bmsim fails, says <pattern>, no <out>.
  function(expect_refused what pattern out)
    execute_process(COMMAND "${BMSIM}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE stdout
                    ERROR_VARIABLE stderr)
    message(STATUS "${what}: exit ${rc}: ${stderr}")
    if(rc EQUAL 0 OR NOT stderr MATCHES "${pattern}")
      message(FATAL_ERROR "${what}: expected a failure saying '${pattern}', got exit ${rc}:\n"
                          "${stdout}\n${stderr}")
    endif()
    if(EXISTS "${out}")
      message(FATAL_ERROR "${what}: left ${out} behind")
    endif()
  endfunction()
  execute_process(COMMAND "${BMSIM}" run glenoid --no-report --device scripted --mode force
                          --duration 0.4 --record "${dir}/rec.csv" --out "${dir}/out" ${small}
                  WORKING_DIRECTORY "${dir}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  message(STATUS "bmsim run glenoid --mode force: exit ${rc}\n${stdout}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the glenoid session failed (${rc}):\n${stderr}")
  endif()
  foreach(key force_scale pause_reason frames removed_volume_mm3 device_max_force_N)
    summary_get(s_${key} "${dir}/out" ${key})
    message(STATUS "summary ${key} = ${s_${key}}")
  endforeach()
  summary_get(s_force_max "${dir}/out" device_force_N)
  string(JSON s_force_max GET "${s_force_max}" max)
  if(NOT s_pause_reason STREQUAL "finished" OR NOT s_frames EQUAL 400 OR NOT s_force_scale EQUAL 50)
    message(FATAL_ERROR "summary: pause ${s_pause_reason}, ${s_frames} frames, scale ${s_force_scale}")
  endif()
  expect_range(device_force_max_N "${s_force_max}" 0.5 3.3)
  file(STRINGS "${dir}/rec.csv" meta LIMIT_COUNT 1)
  if(NOT meta MATCHES "\"force_scale\":50")
    message(FATAL_ERROR "the recording's metadata has no force scale: ${meta}")
  endif()
  execute_process(COMMAND "${BMSIM}" replay "${dir}/rec.csv" --out "${dir}/replay"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  message(STATUS "bmsim replay: exit ${rc}\n${stdout}")
  if(NOT rc EQUAL 0 OR NOT stdout MATCHES "every recorded quantity reproduced" OR NOT EXISTS "${dir}/replay/replay.csv"
     OR NOT EXISTS "${dir}/replay/replay_summary.json")
    message(FATAL_ERROR "the glenoid recording did not replay (${rc}):\n${stderr}")
  endif()
  # The session and replay summaries name the coefficient set and whether it is calibrated.
  foreach(f out/summary.json replay/replay_summary.json)
    file(READ "${dir}/${f}" text)
    string(JSON set_name ERROR_VARIABLE set_err GET "${text}" coefficients name)
    string(JSON set_calibrated ERROR_VARIABLE cal_err GET "${text}" coefficients calibrated)
    if(set_err OR cal_err OR set_name STREQUAL "")
      message(FATAL_ERROR "${f} names no coefficient set: ${set_err} ${cal_err}")
    endif()
    message(STATUS "${f}: coefficients ${set_name}, calibrated ${set_calibrated}")
  endforeach()
  set(cranium /usr/share/doc/invesalius-examples/examples/Cranium.inv3)
  if(EXISTS "${cranium}")
    execute_process(COMMAND "${BMSIM}" run skull --no-report --device scripted --mode hand --force 1
                            --force-scale 5 --duration 0.5 --record "${dir}/skull.csv"
                            --out "${dir}/skull_out" --voxmap-resolution 48 --shell-resolution 64
                    WORKING_DIRECTORY "${dir}"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
    message(STATUS "bmsim run skull --mode hand: exit ${rc}\n${stdout}")
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "the skull session failed (${rc}):\n${stderr}")
    endif()
    summary_get(v "${dir}/skull_out" removed_volume_mm3)
    expect_range(skull_removed_volume_mm3 "${v}" 0 100)
    execute_process(COMMAND "${BMSIM}" replay "${dir}/skull.csv" RESULT_VARIABLE rc
                    OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
    if(NOT rc EQUAL 0 OR NOT stdout MATCHES "every recorded quantity reproduced")
      message(FATAL_ERROR "the skull recording did not replay (${rc}):\n${stdout}\n${stderr}")
    endif()
  endif()
  expect_refused("--force above the Touch's maximum" "must be in \\[0, 3.3\\]" "${dir}/o1"
                 run glenoid --device scripted --mode force --force 4 --out "${dir}/o1" ${small})
  expect_refused("--record into a missing folder" "--record" "${dir}/o2"
                 run glenoid --device scripted --mode force --record /nonexistent/dir/r.csv
                 --out "${dir}/o2" ${small})
  # A recording with an infinite pose: refused before anything runs, nothing written.
  file(STRINGS "${dir}/rec.csv" lines)
  list(GET lines 0 l0)
  list(GET lines 1 l1)
  list(GET lines 2 l2)
  # Only the third field (device_x_mm): REGEX REPLACE would repeat "^..." along the line.
  string(REGEX MATCH "^([^,]*,[^,]*,)[^,]*(.*)$" unused "${l2}")
  set(l2 "${CMAKE_MATCH_1}inf${CMAKE_MATCH_2}")
  file(WRITE "${dir}/bad.csv" "${l0}\n${l1}\n${l2}\n")
  expect_refused("a recording with an infinite pose" "non-finite device position" "${dir}/o3"
                 replay "${dir}/bad.csv" --out "${dir}/o3")

else()
  message(FATAL_ERROR "unknown MODE '${MODE}'")
endif()
message(STATUS "bmsim run ${MODE}: passed")
