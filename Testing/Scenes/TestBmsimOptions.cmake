# bmsim's command line (CLI11, Docs/CommandLine.md): every command's --help exits 0 and lists its
# options; bad use exits 2 with a message naming the option (and its range); --device is the
# haptic device only, the OpenCL device is --cl-device. Nothing here runs a simulation.
# Args: -DBMSIM=.
function(expect_exit code expected)
  execute_process(COMMAND "${BMSIM}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL ${code} OR NOT "${out}${err}" MATCHES "${expected}")
    message(FATAL_ERROR "bmsim ${ARGN}: exit ${rc} (expected ${code}), output does not match "
                        "'${expected}':\n${out}${err}")
  endif()
endfunction()

expect_exit(0 "Subcommands:.*import.*run" --help)
expect_exit(0 "bmsim \\(BoneMachining\\) [0-9.]+.*resources: " --version)
expect_exit(2 "A subcommand is required")
expect_exit(2 "unknown command 'frobnicate'" frobnicate)
execute_process(COMMAND "${BMSIM}" --help OUTPUT_VARIABLE help)
string(REGEX MATCH "Subcommands:.*" subs "${help}")
string(REGEX MATCHALL "\n  ([a-z]+) " names "${subs}")
list(LENGTH names count)
if(count LESS 6)
  message(FATAL_ERROR "bmsim --help lists ${count} commands:\n${help}")
endif()
foreach(n ${names})
  string(STRIP "${n}" n)
  expect_exit(0 "Usage: bmsim ${n} \\[OPTIONS\\]" ${n} --help)
endforeach()
expect_exit(0 "--voxmap-resolution INT:in \\[8, 4096\\].*--cl-device D.*--device WORD:\\{scripted,touch\\}"
            run --help)

expect_exit(2 "The following argument was not expected: --bogus" run drilling --bogus)
expect_exit(2 "--voxmap-resolution: must be in \\[8, 4096\\], got 5" run drilling --voxmap-resolution 5)
expect_exit(2 "--feed: needs a number in \\[1e-05, 1\\], got 'fast'" run drilling --feed fast)
expect_exit(2 "--threads: needs an integer in \\[1, 64\\], got '2.5'" run drilling --threads 2.5)
expect_exit(2 "--shell-resolution: 1 required" run drilling --shell-resolution)
expect_exit(2 "--device: 0 not in \\{scripted,touch\\}" run drilling --device 0)
expect_exit(2 "--method: euler not in \\{lazar,zheng\\}" run drilling --method euler)
expect_exit(2 "needs exactly one SCENE" run)
expect_exit(2 "--resolution: must be in \\[8, 8192\\], got 100000" import x.nrrd --out y.nrrd --resolution 100000)
expect_exit(2 "--max-memory: must be in \\[1, 1e\\+09\\], got 0" import x.nrrd --out y.nrrd --max-memory 0)
expect_exit(2 "--push: must be in \\[0.01, 3.3\\], got 10" bench --session drilling --push 10)
expect_exit(2 "--tolerance: must be in \\[0, 1e\\+06\\], got -1" replay r.csv --tolerance -1)
expect_exit(2 "--target-version: must be in \\[-44.9, 44.9\\], got 60" plan phantom --out x --target-version 60)
message(STATUS "bmsim options: passed")
