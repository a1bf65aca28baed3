# Fuzz.<Name>: one fuzz target for RUNS executions from its seed corpus. Arguments: FUZZER (the
# executable), CORPUS (seed folder, never written), WORK_DIR (new inputs and crash artifacts),
# RUNS, SEED (0: random). Fails, printing the fuzzer's report and the input that did it, on any
# finding: a crash, a sanitizer report, an uncaught exception, a leak, a timeout or out of memory.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/new ${WORK_DIR}/artifacts)
set(ENV{ASAN_OPTIONS} "detect_leaks=1:abort_on_error=0:allocator_may_return_null=0")
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
# The loader targets write each input to a file: in memory (/dev/shm) that is fifty times faster
# than on a disk.
if(IS_DIRECTORY /dev/shm)
  set(ENV{TMPDIR} /dev/shm)
endif()
execute_process(COMMAND ${FUZZER} -runs=${RUNS} -seed=${SEED} -max_len=8192 -timeout=10 -rss_limit_mb=2048
                        -malloc_limit_mb=1024 -print_final_stats=1 -artifact_prefix=${WORK_DIR}/artifacts/
                        ${WORK_DIR}/new ${CORPUS}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCH "stat::number_of_executed_units: *[0-9]+" executed "${err}")
message(STATUS "${FUZZER}: ${executed}")
if(NOT rc EQUAL 0)
  # The next run starts by removing WORK_DIR: the inputs that did it are also copied to a folder
  # beside it that no run removes, so a rerun cannot lose them.
  file(GLOB found ${WORK_DIR}/artifacts/*)
  string(TIMESTAMP stamp "%Y%m%d-%H%M%S")
  set(kept ${WORK_DIR}-findings/${stamp})
  file(MAKE_DIRECTORY ${kept})
  if(found)
    file(COPY ${found} DESTINATION ${kept})
  endif()
  file(WRITE ${kept}/report.txt "${err}")
  string(REGEX MATCH "Seed: [0-9]+" seed_used "${err}")
  message(FATAL_ERROR "the fuzzer found a problem (exit code ${rc}, ${seed_used}); input and report kept in ${kept}\n"
                      "Keep it as a regression case in ${CORPUS} and in a unit test.\n${err}")
endif()
