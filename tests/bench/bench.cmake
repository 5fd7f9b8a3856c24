# The benchmark suite (bench/run.sh) runs in --quick mode and writes its CSV and Markdown.
# A smoke test only: no timing is asserted.
add_test(NAME bench.quick
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/bench/bench_smoke.sh $<TARGET_FILE:pvrt> ${CMAKE_CURRENT_BINARY_DIR}/bench-quick)
set_tests_properties(bench.quick PROPERTIES LABELS bench TIMEOUT 600)

# The paper's experiments (bench/paper.sh) at tiny sizes: every figure, CSV and the report are written and the
# model's and the simulator's predictions are finite numbers. No timing is asserted.
add_test(NAME experiments.paper.quick
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/bench/paper_smoke.sh $<TARGET_FILE:pvrt> ${CMAKE_CURRENT_BINARY_DIR}/paper-quick)
set_tests_properties(experiments.paper.quick PROPERTIES LABELS experiments TIMEOUT 900 RUN_SERIAL TRUE)

# bench/many_core.sh (the scaling measurements for a borrowed many-core machine) in --quick mode here, through a
# bundle of wrappers: its parts run and its 8 files are written. No timing is asserted.
add_test(NAME bench.many_core.quick
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/bench/many_core_smoke.sh $<TARGET_FILE:pvrt> ${CMAKE_CURRENT_BINARY_DIR}/many-core-quick)
set_tests_properties(bench.many_core.quick PROPERTIES LABELS bench TIMEOUT 600 RUN_SERIAL TRUE)
