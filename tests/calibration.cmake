# `remotetouch calibrate ...` as a user meets it. Included by tests/CMakeLists.txt.
#
# The file doubles as a checker, run as `cmake -DKIND=... -DJSON=... -P calibration.cmake`:
# it reads a JSON file the command wrote and fails unless the fields the rest of the system
# reads are there (CMake's string(JSON) is the only JSON reader a ctest line has).
if(CMAKE_SCRIPT_MODE_FILE)
  file(READ "${JSON}" document)
  function(require_number path_text)
    string(REPLACE "." ";" path "${path_text}")
    string(JSON value ERROR_VARIABLE error GET "${document}" ${path})
    if(error OR NOT value MATCHES "^-?[0-9]+(\\.[0-9]+)?([eE][-+]?[0-9]+)?$")
      message(FATAL_ERROR "${JSON}: '${path_text}' is not a number (${value}${error})")
    endif()
  endfunction()
  function(require_length path_text expected)
    string(REPLACE "." ";" path "${path_text}")
    string(JSON length ERROR_VARIABLE error LENGTH "${document}" ${path})
    if(error OR NOT length EQUAL expected)
      message(FATAL_ERROR "${JSON}: '${path_text}' has ${length} entries, expected ${expected} ${error}")
    endif()
  endfunction()
  if(KIND STREQUAL "intrinsics")
    foreach(field width height fx fy cx cy rms_error_px distortion.k1 distortion.k2 distortion.p1 distortion.p2
                  distortion.k3 per_image.0.rms_error_px std_dev_px.fx)
      require_number(${field})
    endforeach()
    require_length(per_image 13)
    string(JSON missing GET "${document}" board_not_found 0)
    if(NOT missing MATCHES "/left\\.jpg$")
      message(FATAL_ERROR "${JSON}: board_not_found should name left.jpg, names '${missing}'")
    endif()
    string(JSON rms GET "${document}" rms_error_px)
    if(NOT rms LESS 0.3)
      message(FATAL_ERROR "${JSON}: RMS reprojection error ${rms} px, expected below 0.3 px")
    endif()
  elseif(KIND STREQUAL "site")
    # The site file (engine/sim/site_description.h): calibrated parts and the kept ones.
    require_number(screen.width_m)
    require_number(seat.head_centre_m.2)
    require_number(motor.position_m.0)
    require_length(cameras 6)
    foreach(camera RANGE 5)
      require_number(cameras.${camera}.fx)
      require_number(cameras.${camera}.distortion.k1)
      require_length(cameras.${camera}.camera_from_site 4)
      require_number(cameras.${camera}.camera_from_site.2.3)
      require_number(cameras.${camera}.depth.fx)
    endforeach()
    require_number(tracker.site_from_tracker.0.3)
    require_number(tracker.rms_residual_mm)
    require_number(tracker.range.max_distance_m)
  else()
    message(FATAL_ERROR "unknown KIND '${KIND}'")
  endif()
  return()
endif()

set(calibration_out ${CMAKE_BINARY_DIR}/test-out/calibration)
set(opencv_data /usr/share/doc/opencv-doc/examples/data)
set(checker ${CMAKE_CURRENT_LIST_FILE})

add_cli_test(calibrate_help 0 "intrinsics.*extrinsics.*tracker.*synthesize" ${rt} calibrate --help)
foreach(step intrinsics synthesize)
  add_cli_test(calibrate_${step}_help 0 "--out.*--device TEXT *Not used" ${rt} calibrate ${step} --help)
endforeach()
# These two update a site file in place instead of writing an --out.
foreach(step extrinsics tracker)
  add_cli_test(calibrate_${step}_help 0 "--site TEXT REQUIRED *Site file to update in place.*--device TEXT *Not used"
               ${rt} calibrate ${step} --help)
endforeach()
add_cli_test(calibrate_without_step 106 "remotetouch calibrate: a subcommand .see remotetouch calibrate --help. is required" ${rt} calibrate)

# The real photographs: the board is found in the 13 leftNN.jpg, not in left.jpg (a scene).
add_cli_test(calibrate_intrinsics_opencv_doc 0
             "found in 13 of 14 images.*board not found in:.*left\\.jpg.*left14\\.jpg.*RMS reprojection error 0\\.[0-2][0-9]* px over 13 images.*wrote"
             ${rt} calibrate intrinsics --images "${opencv_data}/left*.jpg" --board 9x6 --square 0.025
                   --device unused --out ${calibration_out}/left_intrinsics.json)
set_tests_properties(calibrate_intrinsics_opencv_doc PROPERTIES FIXTURES_SETUP calibration_left_intrinsics)
add_test(NAME calibrate_intrinsics_json
         COMMAND ${CMAKE_COMMAND} -DKIND=intrinsics -DJSON=${calibration_out}/left_intrinsics.json -P ${checker})
set_tests_properties(calibrate_intrinsics_json PROPERTIES FIXTURES_REQUIRED calibration_left_intrinsics)

add_cli_test(calibrate_intrinsics_bad_board 1 "remotetouch: error: board '9by6': expected COLSxROWS"
             ${rt} calibrate intrinsics --images "${opencv_data}/left*.jpg" --board 9by6 --square 0.025
                   --out ${calibration_out}/unused.json)
add_cli_test(calibrate_intrinsics_wrong_board 1
             "remotetouch: error: the board \\(10x7 inner corners, 25 mm squares\\) was found in 0 of 4 images.*left01\\.jpg"
             ${rt} calibrate intrinsics --images "${opencv_data}/left0[1-4].jpg" --board 10x7 --square 0.025
                   --out ${calibration_out}/unused.json)
add_cli_test(calibrate_intrinsics_square_in_mm 1 "remotetouch: error: square size 25 m .*in metres \\(25 mm is 0.025\\)"
             ${rt} calibrate intrinsics --images "${opencv_data}/left*.jpg" --board 9x6 --square 25)
add_cli_test(calibrate_intrinsics_no_images 1 "remotetouch: error: images '.*none\\*\\.jpg': the pattern matches no file"
             ${rt} calibrate intrinsics --images "${calibration_out}/none*.jpg" --board 9x6 --square 0.025)
add_cli_test(calibrate_intrinsics_too_few 1 "remotetouch: error: .*found in 2 of 2 images, at least 3 are needed"
             ${rt} calibrate intrinsics --images ${opencv_data}/left01.jpg ${opencv_data}/left02.jpg
                   --board 9x6 --square 0.025)

# A simulated site, calibrated step by step into a copy of the default site file.
add_cli_test(calibrate_synthesize 0 "6 cameras, 24 chessboard views, 20 touches \\(3 slipped\\).*cp assets/sites/default.json SITE.json"
             ${rt} calibrate synthesize --out ${calibration_out}/synthetic)
set_tests_properties(calibrate_synthesize PROPERTIES FIXTURES_SETUP calibration_synthetic)
add_test(NAME calibrate_site_copy
         COMMAND ${CMAKE_COMMAND} -E copy ${CMAKE_SOURCE_DIR}/assets/sites/default.json ${calibration_out}/site.json)
set_tests_properties(calibrate_site_copy PROPERTIES FIXTURES_SETUP calibration_site_copy)
add_cli_test(calibrate_extrinsics_synthetic 0
             "top-centre +\\(reference\\).*bottom-right +bottom-centre +[0-9]+ .*alignment RMS [0-4]\\.[0-9]+ mm.*updated .*site\\.json \\(6 cameras: color intrinsics and poses; kept the tracker"
             ${rt} calibrate extrinsics --input ${calibration_out}/synthetic/extrinsics_input.json
                   --site ${calibration_out}/site.json)
set_tests_properties(calibrate_extrinsics_synthetic PROPERTIES
  FIXTURES_REQUIRED "calibration_synthetic;calibration_site_copy" FIXTURES_SETUP calibration_site_cameras)
# The three touches rejected are the three the synthetic site slipped (truth_touch_outliers.json).
add_cli_test(calibrate_tracker_synthetic 0
             "row1-col3 +[0-9.]+ mm  rejected.*row2-col0 +[0-9.]+ mm  rejected.*row3-col4 +[0-9.]+ mm  rejected.*rejected 3 of 20 touches.*residual RMS [2-3]\\.[0-9]+ mm over the 17 touches kept.*updated .*site\\.json \\(tracker pose; kept the cameras"
             ${rt} calibrate tracker --input ${calibration_out}/synthetic/tracker_touches.json
                   --site ${calibration_out}/site.json)
set_tests_properties(calibrate_tracker_synthetic PROPERTIES
  FIXTURES_REQUIRED "calibration_synthetic;calibration_site_cameras" FIXTURES_SETUP calibration_site_full)
add_test(NAME calibrate_site_json COMMAND ${CMAKE_COMMAND} -DKIND=site -DJSON=${calibration_out}/site.json -P ${checker})
set_tests_properties(calibrate_site_json PROPERTIES FIXTURES_REQUIRED calibration_site_full)

# CLI11's own file check (ValidationError).
add_cli_test(calibrate_tracker_missing_input 105 "--input: File does not exist"
             ${rt} calibrate tracker --input ${calibration_out}/no-such-touches.json --site ${calibration_out}/site.json)
add_cli_test(calibrate_tracker_missing_site 1
             "remotetouch: error: site file '.*no-such-site\\.json' does not exist: start from a copy of assets/sites/default\\.json"
             ${rt} calibrate tracker --input ${calibration_out}/synthetic/tracker_touches.json
                   --site ${calibration_out}/no-such-site.json)
set_tests_properties(calibrate_tracker_missing_site PROPERTIES FIXTURES_REQUIRED calibration_synthetic)
# A --site that is not a site file (here: a camera JSON) is not overwritten.
add_cli_test(calibrate_tracker_foreign_site 1 "remotetouch: error: '.*left_intrinsics\\.json' is not a site file to update"
             ${rt} calibrate tracker --input ${calibration_out}/synthetic/tracker_touches.json
                   --site ${calibration_out}/left_intrinsics.json)
set_tests_properties(calibrate_tracker_foreign_site PROPERTIES
  FIXTURES_REQUIRED "calibration_synthetic;calibration_left_intrinsics")
add_cli_test(calibrate_extrinsics_wrong_input 1
             "remotetouch: error: extrinsics input '.*tracker_touches\\.json': missing field 'board'"
             ${rt} calibrate extrinsics --input ${calibration_out}/synthetic/tracker_touches.json
                   --site ${calibration_out}/unused.json)
set_tests_properties(calibrate_extrinsics_wrong_input PROPERTIES FIXTURES_REQUIRED calibration_synthetic)
