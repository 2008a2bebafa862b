# The hand tracker live (`site --tracker leap`): a fake Leap service serving the clap's tracker
# frames, a site reading them as its hands while it plays against a simulated peer; a bad value
# and a missing service are clear errors, the second before any peer is awaited.
add_executable(fake_leap_service ${CMAKE_CURRENT_LIST_DIR}/tools/fake_leap_service.cpp)
target_link_libraries(fake_leap_service PRIVATE remotetouch_test_common)
add_test(NAME session_site_leap_tracker
         COMMAND ${CMAKE_CURRENT_LIST_DIR}/cli/session_leap.sh $<TARGET_FILE:remotetouch> $<TARGET_FILE:fake_leap_service>
                 ${CMAKE_SOURCE_DIR}/assets/scenes/clap.json ${CMAKE_BINARY_DIR}/test-out/session-leap)
set_tests_properties(session_site_leap_tracker PROPERTIES TIMEOUT 300 RUN_SERIAL TRUE)
add_cli_test(session_site_bad_tracker 105 "--tracker: 'kinect' is not a tracker: scene, leap, or leap:ws://"
             $<TARGET_FILE:remotetouch> site --tracker kinect)
add_cli_test(session_site_bad_tracker_url 105 "--tracker: Leap service URL 'http://127.0.0.1' must start with ws://"
             $<TARGET_FILE:remotetouch> site --tracker leap:http://127.0.0.1)
# A key as keygen makes them (a regular one is refused as hand-typed before the tracker is tried).
file(WRITE ${CMAKE_BINARY_DIR}/test-out/leap-key/session.key "ef4c138bc13e1d1eef4148b0ac1e2341c56d40ce7f6250f97978354b6794b7eb\n")
file(CHMOD ${CMAKE_BINARY_DIR}/test-out/leap-key/session.key PERMISSIONS OWNER_READ OWNER_WRITE)
add_cli_test(session_site_no_leap_service 1
             "remotetouch: error: no Leap service answers at ws://127.0.0.1:1/v6.json within 3000 ms: cannot connect: Connection refused"
             $<TARGET_FILE:remotetouch> site --site A --tracker leap:ws://127.0.0.1:1/v6.json
             --key-file ${CMAKE_BINARY_DIR}/test-out/leap-key/session.key --width 32 --height 18 --resolution-scale 0.05
             --out ${CMAKE_BINARY_DIR}/test-out/site-no-leap)
