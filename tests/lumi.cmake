# The OpenCV DNN peer check of Lumi-Net needs OpenCV's dnn module, which only this test links.
find_package(OpenCV REQUIRED COMPONENTS dnn)
target_link_libraries(remotetouch_gpu_tests PRIVATE opencv_dnn)

# Lumi-Net's training data as a user exports it (a tiny target), and its refusals.
set(rt $<TARGET_FILE:remotetouch>)
add_cli_test(cli_export_lumi 0 "export lumi: scene miss.*at 1/2 \\(17x9\\), 4 views.*wrote 2 frames"
             ${rt} export lumi --scene miss --frames 2 --frame-step 30 --width 33 --height 17 --supersample 1
             --out ${CMAKE_BINARY_DIR}/test-out/export-lumi)
add_cli_test(cli_export_lumi_bad_scale 105 "--scale: 3 not in" ${rt} export lumi --scale 3)

# --blend lumi through the image-based model's options, and bench lumi, tiny.
add_test(NAME cli_eval_ibr_lumi
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/eval_ibr_lumi.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/eval-ibr-lumi)
add_cli_test(cli_eval_ibr_bad_blend 105 "--blend: lumigraph not in \\{ulr,lumi\\}" ${rt} eval ibr --blend lumigraph)
add_cli_test(cli_bench_lumi 0
             "network at 17x9.*Lumi-Net layers, GPU kernels +[0-9.]+.*OpenCV DNN \\(ONNX\\) +[0-9.]+.*ULR blend.*OpenCV DNN / kernels: [0-9.]+x"
             ${rt} bench lumi --frames 1 --width 33 --height 17 --validation --out ${CMAKE_BINARY_DIR}/test-out/bench-lumi)
add_cli_test(cli_bench_lumi_bad_onnx 105 "--onnx: File does not exist" ${rt} bench lumi --onnx no-such.onnx)
