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

foreach(sub render generate)
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
pvrt_expect_error(missing_file 3 "no-such\\.xml: error: cannot read"
  $<TARGET_FILE:pvrt> render ${BAD}/no-such.xml -o ${PVRT_E2E_DIR}/missing_file.png)
pvrt_expect_error(directory_as_scene 3 "bad: error: cannot read"
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
