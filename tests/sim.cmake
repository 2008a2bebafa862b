# The simulated sites (engine/sim/, assets/sites/, assets/scenes/).

# Rewrites assets/sites/*.json from the generator in engine/sim/default_site.cpp.
add_custom_target(regenerate_sim_sites
  COMMAND remotetouch_cpu_tests "[.regenerate]"
  DEPENDS remotetouch_cpu_tests
  COMMENT "Regenerating assets/sites/*.json from engine/sim/default_site.cpp")
