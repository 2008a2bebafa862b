# The image-based model's commands, as a user runs them (small sizes).
add_test(NAME cli_eval_ibr_outputs
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/eval_ibr_outputs.sh $<TARGET_FILE:remotetouch> ${CMAKE_BINARY_DIR}/test-out/eval-ibr)
set(rt $<TARGET_FILE:remotetouch>)
add_cli_test(cli_eval_ibr_unknown_scene 1 "remotetouch: error: unknown scene 'no-such-scene': the scenes are approach, av-marker, clap"
             ${rt} eval ibr --scene no-such-scene --frames 1)
add_cli_test(cli_eval_ibr_unknown_camera 1 "remotetouch: error: no camera named 'no-such-camera'"
             ${rt} eval ibr --frames 1 --cameras top-centre,no-such-camera)
# CLI11's ExcludesError.
add_cli_test(cli_eval_ibr_cameras_and_views 108 "--views excludes --cameras" ${rt} eval ibr --cameras top-centre --views 2)
add_cli_test(cli_eval_ibr_bad_fusion 105 "--fusion: median not in" ${rt} eval ibr --fusion median)
add_cli_test(cli_eval_ibr_bad_edge_inset 105 "--edge-inset: Value 0.5 not in range" ${rt} eval ibr --edge-inset 0.5)
add_cli_test(cli_bench_ibr 0 "roofline .*buffer transfer.*host memcpy.*FMA peak.*6 views: image-based model.*% roofline +GFLOP/s +% peak.*ibr_warp_blend +[0-9.]+ +[0-9]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+[^a-z]*(ibr_fill +[0-9.]+ +[0-9]+ +[0-9.]+ +[0-9.]+ +[0-9.]+[^a-z]*)?sum of medians.*warp's arithmetic .*[0-9]+ seen; [0-9.]+ MFLOP with the blend.*CPU peer \\(OpenCV.*GPU [0-9.]+x the peer.s speed; portraits agree to ([4-9][0-9]|[1-9][0-9][0-9])\\.[0-9] dB, alpha differs on 0\\.[0-4][0-9] % of the covered pixels"
             ${rt} bench ibr --frames 1 --width 65 --height 33 --out ${CMAKE_BINARY_DIR}/test-out/bench-ibr)
# --split-warp: the peer is then the split path, and the other GPU path is the one pass.
add_cli_test(cli_bench_ibr_split_warp 0 "ibr_warp .*ibr_blend .*GPU's ibr_warp \\+ ibr_blend .*one pass \\(ibr_warp_blend\\) [0-9.]+ ms, split \\(ibr_warp \\+ ibr_blend\\) [0-9.]+ ms.*differ by at most"
             ${rt} bench ibr --split-warp --views 2 --frames 1 --width 33 --height 17 --out ${CMAKE_BINARY_DIR}/test-out/bench-ibr-split)
# The dual hand at the glass: the receiver's whole chain per touch phase and variant, small.
add_test(NAME cli_eval_dual_outputs
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/eval_dual_outputs.sh $<TARGET_FILE:remotetouch> ${CMAKE_BINARY_DIR}/test-out/eval-dual)
add_test(NAME cli_eval_dual_prediction
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/eval_dual_prediction.sh $<TARGET_FILE:remotetouch> ${CMAKE_BINARY_DIR}/test-out/eval-dual-prediction)
add_cli_test(cli_eval_dual_bad_latency 105 "--tracker-latency: Value -1 not in range" ${rt} eval dual --tracker-latency -1)
add_cli_test(cli_eval_dual_bad_variant 105 "--variants: blend not in" ${rt} eval dual --variants dual,blend)
add_cli_test(cli_eval_dual_bad_user 105 "--users: C not in" ${rt} eval dual --users C)
add_cli_test(cli_eval_dual_past_end 1 "eval dual: --first-frame 100000 is past the scene's 180 frames"
             ${rt} eval dual --scene clap --first-frame 100000)
# The accuracy-against-time sweep on its tiny grid, its front checked, resumed; --budget-ms and --quality.
add_test(NAME cli_bench_accuracy_outputs
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/bench_accuracy_outputs.sh $<TARGET_FILE:remotetouch> ${CMAKE_BINARY_DIR}/test-out/bench-accuracy)
add_cli_test(cli_bench_accuracy_bad_grid 105 "--grid: huge not in" ${rt} bench accuracy --grid huge)
add_cli_test(cli_bench_accuracy_unknown_scene 1 "remotetouch: error: unknown scene 'no-such-scene': the scenes are approach, av-marker, clap"
             ${rt} bench accuracy --grid tiny --scenes wave,no-such-scene --frames 1 --no-plot
             --out ${CMAKE_BINARY_DIR}/test-out/bench-accuracy-unknown-scene)
add_cli_test(cli_quality_unknown_preset 105 "--quality: .*no preset 'ultra' \\(known: balanced, best, fast\\)"
             ${rt} eval ibr --quality ultra)
add_cli_test(cli_quality_and_budget 108 "--quality excludes --budget-ms" ${rt} eval ibr --quality fast --budget-ms 50)
