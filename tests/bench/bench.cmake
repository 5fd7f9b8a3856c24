# The benchmark suite (bench/run.sh) runs in --quick mode and writes its CSV and Markdown.
# A smoke test only: no timing is asserted.
add_test(NAME bench.quick
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/bench/bench_smoke.sh $<TARGET_FILE:pvrt> ${CMAKE_CURRENT_BINARY_DIR}/bench-quick)
set_tests_properties(bench.quick PROPERTIES LABELS bench TIMEOUT 600)
