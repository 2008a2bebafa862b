# remotetouch eval hand at a small size: it must succeed, print the table and write
# metrics.json with every promised key, each a finite number.
execute_process(COMMAND ${RT} eval hand --width 192 --height 108 --out ${OUT}
                RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "eval hand failed (${result}): ${output} ${errors}")
endif()
foreach(row skinning_max_err_m tip_err_mm "color_de \\(light\\)" "color_de \\(dark\\)" CIEDE2000)
  if(NOT output MATCHES "${row}")
    message(FATAL_ERROR "the table lacks '${row}':\n${output}")
  endif()
endforeach()
file(READ ${OUT}/metrics.json metrics)
foreach(key skinning_max_err_m tip_err_mm_before tip_err_mm_after color_de_before color_de_after
            color_de_before_light color_de_after_light color_de_before_medium color_de_after_medium
            color_de_before_dark color_de_after_dark)
  string(JSON value ERROR_VARIABLE missing GET "${metrics}" ${key})
  if(missing)
    message(FATAL_ERROR "metrics.json has no '${key}': ${missing}")
  endif()
  if(NOT value MATCHES "^-?[0-9]")
    message(FATAL_ERROR "metrics.json '${key}' is not a number: ${value}")
  endif()
endforeach()
string(JSON skinning GET "${metrics}" skinning_max_err_m)
if(skinning GREATER 0.0001)
  message(FATAL_ERROR "GPU skinning is off by ${skinning} m")
endif()
