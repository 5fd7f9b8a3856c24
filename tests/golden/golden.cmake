# Golden-image tests against POV-Ray's renders (label golden), generated from
# reference/manifest.tsv: for every reference, one freshness test per scene, one render
# test per backend, and for a few scenes a fresh POV-Ray render of the reference.
set(PVRT_GOLDEN ${CMAKE_CURRENT_SOURCE_DIR}/golden/golden.sh)
set(PVRT_MANIFEST ${PROJECT_SOURCE_DIR}/reference/manifest.tsv)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PVRT_MANIFEST})
set(PVRT_GOLDEN_BACKENDS serial openmp)
if(PVRT_MPIRUN)
  list(APPEND PVRT_GOLDEN_BACKENDS mpi)
endif()
# POV-Ray re-renders these references in the test suite (others only when regenerated).
set(PVRT_POVRAY_RECHECK paper1 shapes lights)

if(EXISTS ${PVRT_MANIFEST})
  file(STRINGS ${PVRT_MANIFEST} lines)
  list(REMOVE_AT lines 0)
  set(golden_tests "")
  foreach(line ${lines})
    string(REPLACE "\t" ";" fields "${line}")
    list(GET fields 0 scene)
    list(GET fields 1 variant)
    if(variant STREQUAL "aa")
      add_test(NAME golden.fresh.${scene}
        COMMAND ${PVRT_GOLDEN} fresh ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR} ${scene})
      list(APPEND golden_tests golden.fresh.${scene})
    endif()
    foreach(backend ${PVRT_GOLDEN_BACKENDS})
      set(name golden.${scene}.${variant}.${backend})
      add_test(NAME ${name}
        COMMAND ${PVRT_GOLDEN} render ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR} ${scene} ${variant} ${backend})
      list(APPEND golden_tests ${name})
    endforeach()
    if(scene IN_LIST PVRT_POVRAY_RECHECK)
      add_test(NAME golden.povray.${scene}.${variant}
        COMMAND ${PVRT_GOLDEN} povray ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR} ${scene} ${variant})
      list(APPEND golden_tests golden.povray.${scene}.${variant})
    endif()
  endforeach()
  # A clean slate before, and the HTML report of whatever failed after.
  add_test(NAME golden.setup COMMAND ${CMAKE_COMMAND} -E rm -rf ${PROJECT_BINARY_DIR}/golden-report)
  add_test(NAME golden.report COMMAND ${PVRT_GOLDEN} report ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR})
  set_tests_properties(golden.setup PROPERTIES FIXTURES_SETUP golden LABELS golden)
  set_tests_properties(golden.report PROPERTIES FIXTURES_CLEANUP golden LABELS golden)
  set_tests_properties(${golden_tests} PROPERTIES LABELS golden FIXTURES_REQUIRED golden)
endif()
