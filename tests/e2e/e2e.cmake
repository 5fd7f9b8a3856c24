# End-to-end tests of the `pvrt` program, each its own CTest name, labelled e2e.
set(PVRT_E2E_DIR ${CMAKE_CURRENT_BINARY_DIR}/e2e-out)
file(MAKE_DIRECTORY ${PVRT_E2E_DIR})
set(PVRT_EXPECT_ERROR ${CMAKE_CURRENT_SOURCE_DIR}/e2e/expect_error.sh)

# Every scene in scenes/ renders at a small size with every effect it needs.
file(GLOB PVRT_SCENES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/scenes/*.xml)
foreach(scene ${PVRT_SCENES})
  get_filename_component(name ${scene} NAME_WE)
  add_test(NAME e2e.render.${name}
    COMMAND pvrt render ${scene} -o ${PVRT_E2E_DIR}/${name}.png -W 96 -H 60 --spp 4 --quiet)
  set_tests_properties(e2e.render.${name} PROPERTIES LABELS e2e)
endforeach()

foreach(sub render generate accuracy)
  add_test(NAME e2e.help.${sub} COMMAND pvrt ${sub} --help)
  set_tests_properties(e2e.help.${sub} PROPERTIES LABELS e2e PASS_REGULAR_EXPRESSION "Usage|Options")
endforeach()

# Bad input: one `file:line: element: what` line, a documented exit code, no output file.
set(BAD ${CMAKE_CURRENT_SOURCE_DIR}/e2e/bad)
function(pvrt_expect_error name rc regex)
  add_test(NAME e2e.error.${name}
    COMMAND ${PVRT_EXPECT_ERROR} ${rc} ${regex} ${PVRT_E2E_DIR}/${name}.png -- ${ARGN})
  set_tests_properties(e2e.error.${name} PROPERTIES LABELS e2e)
endfunction()
file(GLOB PVRT_BAD_SCENES CONFIGURE_DEPENDS ${BAD}/*.xml)
foreach(scene ${PVRT_BAD_SCENES})
  get_filename_component(name ${scene} NAME_WE)
  pvrt_expect_error(${name} 3 "^.*${name}\\.xml:[0-9]+: [a-z_]+: "
    $<TARGET_FILE:pvrt> render ${scene} -o ${PVRT_E2E_DIR}/${name}.png -W 8 -H 8 --quiet)
endforeach()
pvrt_expect_error(missing_file 3 "no-such\\.xml: cannot read"
  $<TARGET_FILE:pvrt> render ${BAD}/no-such.xml -o ${PVRT_E2E_DIR}/missing_file.png)
pvrt_expect_error(directory_as_scene 3 "bad: cannot read"
  $<TARGET_FILE:pvrt> render ${BAD} -o ${PVRT_E2E_DIR}/directory_as_scene.png)
pvrt_expect_error(bad_extension 2 "unsupported image format"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/bad_extension.bmp)
pvrt_expect_error(spp_not_square 2 "perfect square"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/spp_not_square.png --spp 5)
pvrt_expect_error(spp_zero 2 "spp"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/spp_zero.png --spp 0)
pvrt_expect_error(unknown_schedule 2 "unknown schedule"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/unknown_schedule.png --schedule fastest)
pvrt_expect_error(output_dir_missing 4 "no such directory"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/nope/output_dir_missing.png)

# `pvrt accuracy`: the settings asked for, and the readings with exact answers.
add_test(NAME e2e.accuracy.table
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/e2e/accuracy_check.sh $<TARGET_FILE:pvrt>
    ${PROJECT_SOURCE_DIR}/scenes/paper1.xml ${PROJECT_SOURCE_DIR}/reference/paper1.png ${PVRT_E2E_DIR}/accuracy)
add_test(NAME e2e.accuracy.plot
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/e2e/accuracy_plot.sh $<TARGET_FILE:pvrt>
    ${PROJECT_SOURCE_DIR}/scenes/paper1.xml ${PVRT_E2E_DIR}/accuracy-plot)
set_tests_properties(e2e.accuracy.table e2e.accuracy.plot PROPERTIES LABELS e2e)
set_tests_properties(e2e.accuracy.plot PROPERTIES SKIP_RETURN_CODE 77)
pvrt_expect_error(accuracy_spp_not_square 2 "perfect square"
  $<TARGET_FILE:pvrt> accuracy ${PROJECT_SOURCE_DIR}/scenes/paper1.xml --spp-list 1,5 --csv ${PVRT_E2E_DIR}/accuracy_spp_not_square.png)
pvrt_expect_error(accuracy_unknown_sampler 2 "unknown sampler"
  $<TARGET_FILE:pvrt> accuracy ${PROJECT_SOURCE_DIR}/scenes/paper1.xml --samplers pov,halton --csv ${PVRT_E2E_DIR}/accuracy_unknown_sampler.png)
pvrt_expect_error(accuracy_reference_size 2 "is 160 x 100, the render would be 100 x 100"
  $<TARGET_FILE:pvrt> accuracy ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -W 100 -H 100
    --reference ${PROJECT_SOURCE_DIR}/reference/paper1.png --csv ${PVRT_E2E_DIR}/accuracy_reference_size.png)
pvrt_expect_error(accuracy_plot_not_png 2 "--plot must name a .png"
  $<TARGET_FILE:pvrt> accuracy ${PROJECT_SOURCE_DIR}/scenes/paper1.xml --plot ${PVRT_E2E_DIR}/accuracy_plot_not_png.pdf)

# `pvrt render --time-budget`: a square c is chosen and printed; budgets must be positive.
add_test(NAME e2e.time_budget
  COMMAND pvrt render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/time_budget.png -W 32 -H 20
    --time-budget 0.2)
set_tests_properties(e2e.time_budget PROPERTIES LABELS e2e
  PASS_REGULAR_EXPRESSION "time budget 0\\.2 s: pilot 8 x 5 at c=[0-9]+ took [0-9.]+ s .*chose --spp [0-9]+ \\(predicted render")
pvrt_expect_error(time_budget_zero 2 "--time-budget must be a positive number of seconds, got 0"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/time_budget_zero.png --time-budget 0)
pvrt_expect_error(time_budget_negative 2 "--time-budget must be a positive number of seconds, got -1"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/time_budget_negative.png --time-budget -1)
pvrt_expect_error(time_budget_with_spp 2 "excludes"
  $<TARGET_FILE:pvrt> render ${PROJECT_SOURCE_DIR}/scenes/paper1.xml -o ${PVRT_E2E_DIR}/time_budget_with_spp.png --time-budget 1 --spp 4)
