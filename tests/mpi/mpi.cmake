# The MPI backend under real mpirun (label mpi): bit-identical to serial for 1-4 ranks,
# every strategy and gather, hybrid MPI+OpenMP, an injected failure, a slowed rank.
find_program(PVRT_MPIRUN mpirun)
if(NOT PVRT_MPIRUN)
  message(WARNING "mpirun not found: MPI tests disabled")
  return()
endif()
set(PVRT_MPI_CHECK ${CMAKE_CURRENT_SOURCE_DIR}/mpi/mpi_check.sh)
set(PVRT_MPI_SCENE ${PROJECT_SOURCE_DIR}/scenes/paper1.xml)
foreach(np 1 2 3 4)
  foreach(schedule block cyclic tiles dynamic)
    foreach(gather gather recursive-doubling)
      set(name mpi.identical.np${np}.${schedule}.${gather})
      add_test(NAME ${name} COMMAND ${PVRT_MPI_CHECK} identical ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE}
                                    ${np} ${schedule} ${gather})
      set_tests_properties(${name} PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
    endforeach()
  endforeach()
endforeach()
add_test(NAME mpi.hybrid.np2.threads2 COMMAND ${PVRT_MPI_CHECK} identical ${PROJECT_BINARY_DIR}
                                             ${PVRT_MPI_SCENE} 2 cyclic recursive-doubling 2)
add_test(NAME mpi.hybrid.np2.threads2.dynamic COMMAND ${PVRT_MPI_CHECK} identical ${PROJECT_BINARY_DIR}
                                                     ${PVRT_MPI_SCENE} 2 dynamic gather 2)
add_test(NAME mpi.hybrid.np3.threads2.dynamic COMMAND ${PVRT_MPI_CHECK} identical ${PROJECT_BINARY_DIR}
                                                     ${PVRT_MPI_SCENE} 3 dynamic recursive-doubling 2)
# POV-Ray's adaptive antialiasing decides per block: ranks must agree with the serial render.
foreach(schedule block cyclic tiles dynamic)
  foreach(method 1 2)
    set(name mpi.adaptive.np3.${schedule}.m${method})
    add_test(NAME ${name} COMMAND ${PVRT_MPI_CHECK} adaptive ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} 3 ${schedule} ${method})
    set_tests_properties(${name} PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
  endforeach()
endforeach()
add_test(NAME mpi.adaptive.np2.threads2.dynamic.m1
  COMMAND ${PVRT_MPI_CHECK} adaptive ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} 2 dynamic 1 2)
set_tests_properties(mpi.adaptive.np2.threads2.dynamic.m1 PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
foreach(schedule cyclic dynamic)
  add_test(NAME mpi.load_map.np3.${schedule} COMMAND ${PVRT_MPI_CHECK} loadmap ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} 3 ${schedule})
  set_tests_properties(mpi.load_map.np3.${schedule} PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
endforeach()
foreach(gather gather recursive-doubling)
  add_test(NAME mpi.formats.np3.${gather} COMMAND ${PVRT_MPI_CHECK} formats ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} 3 ${gather})
  set_tests_properties(mpi.formats.np3.${gather} PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
endforeach()
add_test(NAME mpi.transports COMMAND ${PVRT_MPI_CHECK} transports ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE})
set_tests_properties(mpi.transports PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
foreach(np 1 2 4)
  add_test(NAME mpi.default_threads.np${np} COMMAND ${PVRT_MPI_CHECK} defaults ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} ${np})
  set_tests_properties(mpi.default_threads.np${np} PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
endforeach()
add_test(NAME mpi.failure_on_one_rank COMMAND ${PVRT_MPI_CHECK} failure ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE})
add_test(NAME mpi.dynamic_slow_rank COMMAND ${PVRT_MPI_CHECK} slow ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE})
set_tests_properties(mpi.hybrid.np2.threads2 mpi.hybrid.np2.threads2.dynamic mpi.hybrid.np3.threads2.dynamic
                     mpi.failure_on_one_rank mpi.dynamic_slow_rank
                     PROPERTIES LABELS mpi TIMEOUT 120 RUN_SERIAL TRUE)
# Interrupting mpirun, and a rank stopped with SIGSTOP (the watchdog, --mpi-timeout).
foreach(sig INT TERM USR1)
  add_test(NAME mpi.interrupt.${sig} COMMAND ${PVRT_MPI_CHECK} interrupt ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} ${sig})
  set_tests_properties(mpi.interrupt.${sig} PROPERTIES LABELS mpi TIMEOUT 60 RUN_SERIAL TRUE)
endforeach()
foreach(sig INT TERM)
  add_test(NAME mpi.interrupt.wrapper.${sig}
    COMMAND ${PVRT_MPI_CHECK} interrupt ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} ${sig} wrapper)
  set_tests_properties(mpi.interrupt.wrapper.${sig} PROPERTIES LABELS mpi TIMEOUT 60 RUN_SERIAL TRUE)
endforeach()
add_test(NAME mpi.stopped_rank COMMAND ${PVRT_MPI_CHECK} stopped ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE})
add_test(NAME mpi.stopped_rank.remote
  COMMAND ${PVRT_MPI_CHECK} stopped ${PROJECT_BINARY_DIR} ${PVRT_MPI_SCENE} remote)
set_tests_properties(mpi.stopped_rank mpi.stopped_rank.remote PROPERTIES LABELS mpi TIMEOUT 60 RUN_SERIAL TRUE)

# A render region under mpirun (3 ranks, every strategy): the whole image's pixels, cut out.
add_test(NAME mpi.region COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/e2e/region_check.sh $<TARGET_FILE:pvrt> ${PVRT_MPI_SCENE}
                                 ${CMAKE_CURRENT_BINARY_DIR}/mpi-region ${PVRT_MPIRUN})
set_tests_properties(mpi.region PROPERTIES LABELS mpi TIMEOUT 300 RUN_SERIAL TRUE)
