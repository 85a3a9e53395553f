# Kill-and-resume after an interruption: SIGKILL at a random point of a long command, then a re-run,
# gives the uninterrupted run's results and no partial files. Seeds fixed (printed). validate (the
# FE cache, the hip cache and the study's files) and sample (a hip folder per sampled hip) run with
# the suite; fai and grid, each two minutes on 2 cores, are "long" (scripts/test --long).
foreach(kind grid fai validate sample)
  if(kind STREQUAL "validate" AND NOT TARGET hipfai_fem)
    continue()
  endif()
  add_test(NAME cli.kill_resume_${kind}
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/kill_resume.sh ${kind} 17 $<TARGET_FILE:hipfai>
                   ${CMAKE_BINARY_DIR}/cli-tmp/kill_resume_${kind})
  set(label slow)
  if(kind STREQUAL "fai" OR kind STREQUAL "grid")
    set(label long)
  endif()
  set_tests_properties(cli.kill_resume_${kind} PROPERTIES LABELS "cli;${label}" TIMEOUT 900)
endforeach()
