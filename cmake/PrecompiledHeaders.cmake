# Precompiled headers. nlohmann/json, Eigen, OpenCV's core and Catch2 cost seconds to parse, and
# most units include one of them through our own headers: each library, and the tests as a
# group, parse them once into a precompiled header instead of once a unit.
option(REMOTETOUCH_PCH "Precompile the heavy third-party headers" ON)

set(REMOTETOUCH_PCH_HEADERS
  <algorithm> <array> <cmath> <cstdint> <functional> <map> <memory> <optional> <string> <vector>
  <nlohmann/json.hpp> <Eigen/Core> <Eigen/Geometry> <opencv2/core.hpp>)

# remotetouch_precompile(TARGET [HEADER...]): the common set and the target's own extra headers.
function(remotetouch_precompile target)
  if(REMOTETOUCH_PCH)
    target_precompile_headers(${target} PRIVATE ${REMOTETOUCH_PCH_HEADERS} ${ARGN})
  endif()
endfunction()

# remotetouch_reuse_precompiled(TARGET FROM): TARGET uses FROM's precompiled header, built once.
function(remotetouch_reuse_precompiled target from)
  if(REMOTETOUCH_PCH)
    target_precompile_headers(${target} REUSE_FROM ${from})
  endif()
endfunction()
