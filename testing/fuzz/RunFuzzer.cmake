# Runs one libFuzzer target deterministically: a fixed seed, a fixed number of runs, from the seed corpus in a
# work folder emptied first, no periodic corpus reload (libFuzzer re-reads its folders every second by default,
# which made the inputs tried depend on timing): a verdict that depends on neither the machine's speed nor earlier runs.
# Per-input timeout 300 s: one input of fuzz_scene (the adaptive lookahead inside reflective tubes, an open issue)
# takes 44 s alone and passed 60 s on a loaded machine.
#   cmake -DFUZZER=<exe> -DWORK=<dir> -DCORPUS=<dir> -DSEED=<n> -DRUNS=<n> -DARTIFACTS=<prefix> -P RunFuzzer.cmake
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(ENV{ASAN_OPTIONS} "detect_leaks=0")
execute_process(COMMAND "${FUZZER}" -seed=${SEED} -runs=${RUNS} -reload=0 -max_len=4096 -timeout=300 -rss_limit_mb=2048
                        -max_total_time=600 -print_final_stats=1 -artifact_prefix=${ARTIFACTS} "${WORK}" "${CORPUS}"
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "fuzzer ${FUZZER} failed (exit ${result}): the input is written to ${ARTIFACTS}*")
endif()
