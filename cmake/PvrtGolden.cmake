# pvrt_add_golden_tests(NAME <prefix> SCENES <folder> [REFERENCES <folder>] [BACKENDS serial openmp mpi]
#                       [OUT <folder>] [LABELS <label>...] [POVRAY_RECHECK <scene>...] [PVRT <program>]
#                       [MPIRUN <program>])
#
# Golden-image tests of a suite (a folder of XML scenes and its references, docs/golden.md),
# all through `pvrt golden`, the command anyone runs by hand:
#   <prefix>.SCENE.VARIANT.BACKEND  one per reference in the manifest at configure time and backend
#   <prefix>.new                    every reference and scene that the manifest did not have at
#                                   configure time, found when the test runs: adding a scene and
#                                   its reference needs no cmake re-run (it passes when there are none)
#   <prefix>.povray.SCENE.VARIANT   POV-Ray renders the reference again, pixel for pixel
#   <prefix>.report                 the HTML report and JUnit XML of whatever ran (fixture cleanup):
#                                   fails, and so prints the report's path, when any test failed
function(pvrt_add_golden_tests)
  cmake_parse_arguments(G "" "NAME;SCENES;REFERENCES;OUT;PVRT;MPIRUN" "BACKENDS;LABELS;POVRAY_RECHECK" ${ARGN})
  # Relative folders are the calling CMakeLists.txt's, as elsewhere in CMake.
  get_filename_component(G_SCENES ${G_SCENES} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  if(NOT G_REFERENCES)
    set(G_REFERENCES ${G_SCENES}/reference)
  endif()
  get_filename_component(G_REFERENCES ${G_REFERENCES} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  if(NOT G_OUT)
    set(G_OUT ${CMAKE_CURRENT_BINARY_DIR}/${G_NAME}-out)
  endif()
  if(NOT G_BACKENDS)
    set(G_BACKENDS serial openmp)
  endif()
  if(NOT G_LABELS)
    set(G_LABELS golden)
  endif()
  if(NOT G_PVRT)
    set(G_PVRT $<TARGET_FILE:pvrt>)
  endif()
  set(suite ${G_PVRT} golden run ${G_SCENES} --references ${G_REFERENCES} --out ${G_OUT} --append)
  if(G_MPIRUN)
    list(APPEND suite --mpirun ${G_MPIRUN})
  endif()
  set(manifest ${G_REFERENCES}/manifest.tsv)
  set(known_file ${CMAKE_CURRENT_BINARY_DIR}/${G_NAME}-known.txt)
  set(tests "")
  set(known "")
  if(EXISTS ${manifest})
    # A changed manifest re-runs cmake at the next build, so that new references get names.
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${manifest})
    file(STRINGS ${manifest} lines)
    list(REMOVE_AT lines 0)
    foreach(line ${lines})
      string(REPLACE "\t" ";" fields "${line}")
      list(GET fields 0 scene)
      list(GET fields 1 variant)
      string(APPEND known "${scene}.${variant}\n")
      foreach(backend ${G_BACKENDS})
        set(name ${G_NAME}.${scene}.${variant}.${backend})
        add_test(NAME ${name} COMMAND ${suite} --scene ${scene} --variant ${variant} --backends ${backend} --jobs 1)
        list(APPEND tests ${name})
      endforeach()
      if(scene IN_LIST G_POVRAY_RECHECK)
        set(name ${G_NAME}.povray.${scene}.${variant})
        add_test(NAME ${name} COMMAND ${G_PVRT} golden make ${G_SCENES} ${scene} --variant ${variant}
                                      --references ${G_REFERENCES} --verify)
        list(APPEND tests ${name})
      endif()
    endforeach()
  endif()
  file(WRITE ${known_file} "${known}")
  string(REPLACE ";" "," backends "${G_BACKENDS}")
  add_test(NAME ${G_NAME}.new COMMAND ${suite} --skip-list ${known_file} --backends ${backends})
  list(APPEND tests ${G_NAME}.new)
  add_test(NAME ${G_NAME}.setup COMMAND ${CMAKE_COMMAND} -E rm -rf ${G_OUT}/results)
  add_test(NAME ${G_NAME}.report COMMAND ${G_PVRT} golden report ${G_OUT} --scenes ${G_SCENES}
                                         --references ${G_REFERENCES})
  set_tests_properties(${G_NAME}.setup PROPERTIES FIXTURES_SETUP ${G_NAME} LABELS "${G_LABELS}")
  set_tests_properties(${G_NAME}.report PROPERTIES FIXTURES_CLEANUP ${G_NAME} LABELS "${G_LABELS}")
  set_tests_properties(${tests} PROPERTIES LABELS "${G_LABELS}" FIXTURES_REQUIRED ${G_NAME})
endfunction()
