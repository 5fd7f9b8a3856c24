# The hard cases (label hard): every scene of scenes/hard/ through the scale sweep on the
# serial, OpenMP and MPI backends, each check its own test, checked against its exact
# answer (tests/hard/cases.h; the cases and their figures are in docs/robustness.md).
set(PVRT_HARD_COMMON hard/hard_run.cpp hard/cases.cpp hard/oracle.cpp)
add_executable(hard_case hard/hard_case.cpp ${PVRT_HARD_COMMON})
add_executable(hard_case_mpi hard/hard_case_mpi.cpp ${PVRT_HARD_COMMON})
foreach(t hard_case hard_case_mpi)
  target_link_libraries(${t} PRIVATE pvrt_lib)
  target_compile_definitions(${t} PRIVATE PVRT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endforeach()

# (offset, scale) of the sweep, in hard_case's numbering 0..3.
set(PVRT_HARD_SWEEPS o0_s1 o1e3_s1 o0_s1e-3 o1e4_s1e3)
set(PVRT_HARD_MPI_RESULTS ${CMAKE_CURRENT_BINARY_DIR}/hard-mpi-results.txt)

function(pvrt_hard_tests scene arg label)
  foreach(backend serial openmp)
    add_test(NAME hard.${scene}.${label}.${backend} COMMAND hard_case ${scene} ${arg} ${backend})
    set_tests_properties(hard.${scene}.${label}.${backend} PROPERTIES LABELS hard TIMEOUT 60)
  endforeach()
  if(PVRT_MPIRUN)
    add_test(NAME hard.${scene}.${label}.mpi
             COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/hard/mpi_result.sh ${PVRT_HARD_MPI_RESULTS} ${scene} ${arg})
    set_tests_properties(hard.${scene}.${label}.mpi PROPERTIES LABELS "hard;mpi" FIXTURES_REQUIRED hard_mpi)
  endif()
endfunction()

file(GLOB PVRT_HARD_SCENES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/scenes/hard/*.xml)
foreach(scene_file ${PVRT_HARD_SCENES})
  get_filename_component(scene ${scene_file} NAME_WE)
  if(scene STREQUAL "translate_base")
    # Its own sweep: the whole scene translated, compared with the untranslated image.
    foreach(offset 1e3 1e5 1e7 1e8)
      pvrt_hard_tests(${scene} t${offset} t${offset})
    endforeach()
  else()
    foreach(i RANGE 3)
      list(GET PVRT_HARD_SWEEPS ${i} sweep)
      pvrt_hard_tests(${scene} ${i} ${sweep})
    endforeach()
  endif()
endforeach()

# Every MPI check comes from one mpirun of all the cases (MPI's start-up dominates).
if(PVRT_MPIRUN)
  add_test(NAME hard.mpi_run COMMAND ${PVRT_MPIRUN} --allow-run-as-root --oversubscribe --bind-to none -np 2
                                     $<TARGET_FILE:hard_case_mpi> ${PVRT_HARD_MPI_RESULTS})
  set_tests_properties(hard.mpi_run PROPERTIES LABELS "hard;mpi" TIMEOUT 300 FIXTURES_SETUP hard_mpi)
endif()

# The scene's length unit (docs/robustness.md): two renders that must agree, in process.
add_executable(length_unit hard/length_unit.cpp)
target_link_libraries(length_unit PRIVATE pvrt_lib)
target_compile_definitions(length_unit PRIVATE PVRT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
foreach(scale 1e-6 1e-5 1e-4 1e-3 1e-2 1e-1 1e1 1e2 1e3 1e4 1e5 1e6)
  add_test(NAME hard.length_unit.sweep.${scale} COMMAND length_unit sweep ${scale})
endforeach()
foreach(radius 1e5 1e6 1e7 1e8)
  add_test(NAME hard.length_unit.dome.${radius} COMMAND length_unit dome ${radius})
endforeach()
foreach(radius 1e-9 1e-8 1e-7 1e-6 1e-4)
  add_test(NAME hard.length_unit.speck.${radius} COMMAND length_unit speck ${radius})
endforeach()
get_property(pvrt_length_unit_tests DIRECTORY PROPERTY TESTS)
list(FILTER pvrt_length_unit_tests INCLUDE REGEX "^hard\\.length_unit\\.")
set_tests_properties(${pvrt_length_unit_tests} PROPERTIES LABELS hard TIMEOUT 120)
