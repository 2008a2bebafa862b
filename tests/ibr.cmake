# The image-based model's commands, as a user runs them (small sizes).
add_test(NAME cli_eval_ibr_outputs
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/eval_ibr_outputs.sh $<TARGET_FILE:remotetouch> ${CMAKE_BINARY_DIR}/test-out/eval-ibr)
add_test(NAME cli_eval_ibr_unknown_scene COMMAND $<TARGET_FILE:remotetouch> eval ibr --scene no-such-scene --frames 1)
set_tests_properties(cli_eval_ibr_unknown_scene PROPERTIES PASS_REGULAR_EXPRESSION "no-such-scene")
add_test(NAME cli_eval_ibr_unknown_camera
         COMMAND $<TARGET_FILE:remotetouch> eval ibr --frames 1 --cameras top-centre,no-such-camera)
set_tests_properties(cli_eval_ibr_unknown_camera PROPERTIES PASS_REGULAR_EXPRESSION "no camera named 'no-such-camera'")
add_test(NAME cli_eval_ibr_cameras_and_views COMMAND $<TARGET_FILE:remotetouch> eval ibr --cameras top-centre --views 2)
set_tests_properties(cli_eval_ibr_cameras_and_views PROPERTIES PASS_REGULAR_EXPRESSION "--views excludes --cameras")
add_test(NAME cli_eval_ibr_bad_fusion COMMAND $<TARGET_FILE:remotetouch> eval ibr --fusion median)
set_tests_properties(cli_eval_ibr_bad_fusion PROPERTIES PASS_REGULAR_EXPRESSION "--fusion.*median")
add_test(NAME cli_eval_ibr_bad_edge_inset COMMAND $<TARGET_FILE:remotetouch> eval ibr --edge-inset 0.5)
set_tests_properties(cli_eval_ibr_bad_edge_inset PROPERTIES PASS_REGULAR_EXPRESSION "--edge-inset: Value 0.5 not in range")
add_test(NAME cli_bench_ibr
         COMMAND $<TARGET_FILE:remotetouch> bench ibr --frames 1 --width 65 --height 33 --out ${CMAKE_BINARY_DIR}/test-out/bench-ibr)
set_tests_properties(cli_bench_ibr PROPERTIES PASS_REGULAR_EXPRESSION "6 views: image-based model.*copy")
