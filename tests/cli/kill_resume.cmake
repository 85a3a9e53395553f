# Kill-and-resume after an interruption: SIGKILL at a random point of a long command, then a re-run,
# gives the uninterrupted run's results and no partial files. Seeds fixed (printed); slow tests.
foreach(kind grid fai validate sample)
  if(kind STREQUAL "validate" AND NOT TARGET hipfai_fem)
    continue()
  endif()
  add_test(NAME cli.kill_resume_${kind}
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/kill_resume.sh ${kind} 17 $<TARGET_FILE:hipfai>
                   ${CMAKE_BINARY_DIR}/cli-tmp/kill_resume_${kind})
  set_tests_properties(cli.kill_resume_${kind} PROPERTIES LABELS "cli;slow" TIMEOUT 900)
endforeach()
