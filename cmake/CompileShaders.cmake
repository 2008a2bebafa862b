# remotetouch_compile_shaders(<target> <glsl files...>)
#
# The one place shaders are compiled. Each GLSL file becomes <build>/shaders/<file>.h holding
# `const uint32_t <file_with_underscores>_spirv[]`. glslangValidator writes a depfile, so editing
# an #include (shaders/shared/config.h, shaders/common/*.glsl) rebuilds every shader that uses it.
# A compile error fails the build. SPIR-V 1.5 (Vulkan 1.2), so that devices that report 1.2, as
# they do under RenderDoc 1.24, run the same code. <target> is an INTERFACE library that puts the headers on the
# include path of whatever links it.
function(remotetouch_compile_shaders target)
  set(out_dir ${CMAKE_BINARY_DIR}/shaders)
  file(MAKE_DIRECTORY ${out_dir})
  set(headers)
  foreach(source ${ARGN})
    get_filename_component(file_name ${source} NAME)
    string(REPLACE "." "_" symbol ${file_name})
    set(header ${out_dir}/${file_name}.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2 -g
              -I${CMAKE_SOURCE_DIR}/shaders
              --vn ${symbol}_spirv
              --depfile ${header}.d
              -o ${header} ${source}
      DEPENDS ${source}
      DEPFILE ${header}.d
      COMMENT "glslang ${file_name}"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${target}_compile DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_compile)
  target_include_directories(${target} INTERFACE ${out_dir} ${CMAKE_SOURCE_DIR}/shaders)
endfunction()
