# Two studies started at once on one cache share it: each FE entry solved once, the same results,
# nothing half made left behind (tests/cli/shared_cache.sh). Slow: two `study validate --quick`.
if(TARGET hipfai_fem)
  add_test(NAME cli.shared_cache_validate
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/shared_cache.sh $<TARGET_FILE:hipfai>
                   ${CMAKE_BINARY_DIR}/cli-tmp/shared_cache_validate)
  set_tests_properties(cli.shared_cache_validate PROPERTIES LABELS "cli;slow" TIMEOUT 300)
endif()
