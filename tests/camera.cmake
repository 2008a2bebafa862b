# The RGB-D cameras (devices/camera/): k4a recordings written, read back through FFmpeg, and
# checked against an independent Matroska reader (mkvinfo, Debian mkvtoolnix).
find_program(REMOTETOUCH_MKVINFO mkvinfo)
if(NOT REMOTETOUCH_MKVINFO AND REMOTETOUCH_REQUIRE_ALL_TESTS)
  message(FATAL_ERROR "mkvinfo not found: install mkvtoolnix (scripts/packages.txt)")
endif()
target_compile_definitions(remotetouch_cpu_tests PRIVATE REMOTETOUCH_MKVINFO="${REMOTETOUCH_MKVINFO}")
# The writer's test (test_k4a_recording_writer) also asks libavformat how it sees what we wrote.
target_link_libraries(remotetouch_cpu_tests PRIVATE PkgConfig::FFMPEG)

# simulate --format k4a refuses cameras whose images are not a k4a mode's size, before rendering.
add_cli_test(cli_simulate_k4a_not_a_mode 1
             "k4a: camera 'top-left' has colour 640x360, not a k4a colour resolution \\(1280x720, .*--resolution-scale 1"
             ${rt} simulate --scene clap --format k4a --frames 1 --out ${CMAKE_BINARY_DIR}/test-out/simulate-k4a-refused)

# simulate --format k4a and inspect-camera as a user runs them: one frame of the default site at
# its cameras' own resolution (k4a modes), then the first camera's recording read back.
set(k4a_simulated ${CMAKE_BINARY_DIR}/test-out/simulate-k4a)
add_test(NAME cli_simulate_k4a
         COMMAND ${rt} simulate --scene clap --format k4a --frames 1 --resolution-scale 1 --gt-width 64 --gt-height 36
                 --out ${k4a_simulated})
set_tests_properties(cli_simulate_k4a PROPERTIES FIXTURES_SETUP k4a_simulated TIMEOUT 300)
add_cli_test(cli_inspect_camera 0
             "inspect-camera: 1 captures of '.*top-left.mkv'.*; depth_in_color [0-9.]+ ms a capture [(]depth_in_color_clear [0-9.]+, depth_in_color [0-9.]+, depth_in_color_resolve [0-9.]+[)] on .*, 1 registered[)]"
             ${rt} inspect-camera ${k4a_simulated}/top-left.mkv --frames 3 --out ${k4a_simulated}/inspect-top-left)
set_tests_properties(cli_inspect_camera PROPERTIES FIXTURES_REQUIRED k4a_simulated FIXTURES_SETUP k4a_inspected)
# What it wrote: the depth registered into colour and the coloured points, checked by a reader of
# its own (PNG and PLY in Python's standard library).
add_test(NAME cli_inspect_camera_outputs
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/cli/inspect_camera_outputs.py ${k4a_simulated}/inspect-top-left)
set_tests_properties(cli_inspect_camera_outputs PROPERTIES FIXTURES_REQUIRED "k4a_simulated;k4a_inspected")
add_cli_test(cli_inspect_camera_missing 1 "remotetouch: error: '.*nonexistent.mkv': no such file"
             ${rt} inspect-camera ${CMAKE_BINARY_DIR}/nonexistent.mkv --out ${CMAKE_BINARY_DIR}/test-out/inspect-missing)

# A site of k4a recordings played by eval ibr (against the simulator's images: within 0.3 dB)
# and by the demo as site A's cameras.
add_test(NAME cli_k4a_site_played
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/k4a_site_played.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/k4a-site-played)
set_tests_properties(cli_k4a_site_played PROPERTIES TIMEOUT 600 RUN_SERIAL TRUE)
# bench camera on the simulated recordings: a row of figures for one thread.
add_cli_test(cli_bench_camera 0 "\n1 +6 +1 +[0-9]+\\.[0-9]+ +[0-9]+\\.[0-9]+ +[0-9]+\\.[0-9]+ +[0-9]+\\.[0-9]+ +[0-9]+\\.[0-9]+ +[0-9]+\\.[0-9]"
             ${rt} bench camera ${k4a_simulated} --frames 3 --out ${CMAKE_BINARY_DIR}/test-out/bench-camera)
set_tests_properties(cli_bench_camera PROPERTIES FIXTURES_REQUIRED k4a_simulated)

# A fake libk4a.so.1.4 that serves k4a recordings as connected devices (tests/fake_k4a), so that
# the live backend's own code runs here; test_k4a_live loads it through REMOTETOUCH_K4A_LIBRARY,
# told where it is by REMOTETOUCH_TEST_FAKE_K4A.
add_library(remotetouch_fake_k4a SHARED ${CMAKE_CURRENT_SOURCE_DIR}/fake_k4a/fake_k4a.cpp)
set_target_properties(remotetouch_fake_k4a PROPERTIES OUTPUT_NAME k4a PREFIX lib SUFFIX .so.1.4
                      LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fake-k4a CXX_VISIBILITY_PRESET hidden)
target_include_directories(remotetouch_fake_k4a PRIVATE ${CMAKE_SOURCE_DIR}/devices)
target_link_libraries(remotetouch_fake_k4a PRIVATE PkgConfig::FFMPEG)
add_dependencies(remotetouch_cpu_tests remotetouch_fake_k4a)
set_tests_properties(test_k4a_live PROPERTIES ENVIRONMENT REMOTETOUCH_TEST_FAKE_K4A=$<TARGET_FILE:remotetouch_fake_k4a>)
target_link_libraries(remotetouch_cpu_tests PRIVATE ${CMAKE_DL_LIBS})

# list-cameras as a user meets it: without the k4a library it says what to install; through the
# fake library it lists the simulated recording's device by serial ("<site>-<camera>").
add_cli_test(cli_list_cameras_no_library 1
             "remotetouch: error: live k4a cameras need the k4a library, and '/nonexistent/libk4a.so.1.4' could not be loaded .*Azure Kinect SDK.*Orbbec.*LD_LIBRARY_PATH"
             ${CMAKE_COMMAND} -E env REMOTETOUCH_K4A_LIBRARY=/nonexistent/libk4a.so.1.4 ${rt} list-cameras)
add_cli_test(cli_list_cameras 0 "list-cameras: 1 k4a device[(]s[)] through '.*libk4a.so.1.4'\n  serial [a-z]+-top-left\n"
             ${CMAKE_COMMAND} -E env REMOTETOUCH_K4A_LIBRARY=$<TARGET_FILE:remotetouch_fake_k4a>
             REMOTETOUCH_FAKE_K4A_RECORDINGS=${k4a_simulated}/top-left.mkv ${rt} list-cameras)
set_tests_properties(cli_list_cameras PROPERTIES FIXTURES_REQUIRED k4a_simulated)

# record as a user runs it, through the fake library, on the devices test_k4a_live wrote (a
# master and a subordinate that dropped one capture): every capture written, none left out.
set(k4a_live_devices ${CMAKE_BINARY_DIR}/test-out/test_k4a_live/same)
set_tests_properties(test_k4a_live PROPERTIES FIXTURES_SETUP k4a_live_devices)
add_cli_test(cli_record 0 "record: [0-9.]+ s of 2 cameras into '.*record-cli' [(]captures: 5 4; 0 left out[)]"
             /bin/sh -c "rm -rf '${CMAKE_BINARY_DIR}/test-out/record-cli' && exec \"$@\"" sh ${CMAKE_COMMAND} -E env
             REMOTETOUCH_K4A_LIBRARY=$<TARGET_FILE:remotetouch_fake_k4a>
             REMOTETOUCH_FAKE_K4A_RECORDINGS=${k4a_live_devices}/top-left.mkv:${k4a_live_devices}/top-centre.mkv
             ${rt} record --site ${k4a_live_devices}/live.json --seconds 5 --out ${CMAKE_BINARY_DIR}/test-out/record-cli)
set_tests_properties(cli_record PROPERTIES FIXTURES_REQUIRED k4a_live_devices)

# A site whose cameras run live through the fake library (paced as devices are): the demo with
# a scene whose site A names wave's simulated recordings as devices, and `site --site-file` by
# hand on test_k4a_live's devices, whose lenses are apart (their depth registered into colour).
add_test(NAME cli_k4a_site_live
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/k4a_site_live.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/k4a-site-live
                 $<TARGET_FILE:remotetouch_fake_k4a> ${CMAKE_SOURCE_DIR}/assets/scenes/wave.json
                 ${CMAKE_SOURCE_DIR}/assets/sites/default.json ${k4a_live_devices})
set_tests_properties(cli_k4a_site_live PROPERTIES FIXTURES_REQUIRED k4a_live_devices TIMEOUT 600 RUN_SERIAL TRUE)
# depth_outliers counts the flying pixels it removes on the simulated k4a recording.
set_tests_properties(test_depth_outliers PROPERTIES FIXTURES_REQUIRED k4a_simulated)

# The site calibrated from recordings of its own cameras (calibrate extrinsics --views-from).
add_test(NAME cli_calibrate_from_recording
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/calibrate_from_recording.sh ${rt}
                 ${CMAKE_BINARY_DIR}/test-out/calibrate-from-recording ${CMAKE_SOURCE_DIR}/assets)
set_tests_properties(cli_calibrate_from_recording PROPERTIES TIMEOUT 300)

# record --tracker leap: the hands written beside the cameras, on their clock, and replayed.
add_test(NAME cli_record_with_hands
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/record_with_hands.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/record-with-hands
                 $<TARGET_FILE:remotetouch_fake_k4a> $<TARGET_FILE:fake_leap_service>
                 ${CMAKE_SOURCE_DIR}/assets/scenes/clap.json ${k4a_live_devices})
set_tests_properties(cli_record_with_hands PROPERTIES FIXTURES_REQUIRED k4a_live_devices TIMEOUT 300)
