# The simulated sites (engine/sim/, assets/sites/, assets/scenes/).

# The tests write into the build tree.
file(GLOB remotetouch_sim_tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test_sim_*.cpp)
foreach(source ${remotetouch_sim_tests})
  get_filename_component(name ${source} NAME_WE)
  target_compile_definitions(${name} PRIVATE REMOTETOUCH_TEST_OUTPUT_DIR="${CMAKE_BINARY_DIR}/test-out/${name}")
endforeach()

# Rewrites assets/sites/*.json from the generator in engine/sim/default_site.cpp.
if(TARGET test_sim_site)
  add_custom_target(regenerate_sim_sites
    COMMAND test_sim_site "[.regenerate]"
    DEPENDS test_sim_site
    COMMENT "Regenerating assets/sites/*.json from engine/sim/default_site.cpp")
endif()
