# The libusb motor driver against an Arduino Uno emulated under umockdev. Its source is not
# named test_*.cpp because it must run under umockdev-wrapper (the preload library that shows
# libusb the test bed's sysfs and answers usbdevfs ioctls), not as a plain test.
find_program(REMOTETOUCH_UMOCKDEV_WRAPPER umockdev-wrapper)
if(NOT REMOTETOUCH_UMOCKDEV_WRAPPER)
  message(FATAL_ERROR "The motor's USB test needs umockdev-wrapper: sudo apt-get install umockdev libumockdev-dev")
endif()
add_executable(test_motor_usb ${CMAKE_CURRENT_LIST_DIR}/motor_usb_umockdev.cpp)
target_link_libraries(test_motor_usb PRIVATE remotetouch_test_support remotetouch_motor_emulated_uno)
add_test(NAME test_motor_usb COMMAND ${REMOTETOUCH_UMOCKDEV_WRAPPER} $<TARGET_FILE:test_motor_usb>)
set_tests_properties(test_motor_usb PROPERTIES TIMEOUT 60)

# The firmware itself in simavr, when its library is installed (Debian: libsimavr-dev). Not
# required: the parser is covered by test_motor_protocol either way. Without simavr the test is
# still registered and reports itself skipped (exit 77), saying what is missing.
find_path(REMOTETOUCH_SIMAVR_INCLUDE_DIR sim_avr.h PATH_SUFFIXES simavr)
find_library(REMOTETOUCH_SIMAVR_LIBRARY simavr)
if(REMOTETOUCH_SIMAVR_INCLUDE_DIR AND REMOTETOUCH_SIMAVR_LIBRARY)
  add_executable(test_motor_firmware_sim ${CMAKE_CURRENT_LIST_DIR}/motor_firmware_simavr.cpp)
  target_include_directories(test_motor_firmware_sim SYSTEM PRIVATE ${REMOTETOUCH_SIMAVR_INCLUDE_DIR})
  target_link_libraries(test_motor_firmware_sim PRIVATE remotetouch_test_support_cpu ${REMOTETOUCH_SIMAVR_LIBRARY})
  target_compile_definitions(test_motor_firmware_sim PRIVATE
    REMOTETOUCH_MOTOR_FIRMWARE_ELF="$<TARGET_PROPERTY:remotetouch_motor_firmware,REMOTETOUCH_ELF>")
  add_dependencies(test_motor_firmware_sim remotetouch_motor_firmware)
  add_test(NAME test_motor_firmware_sim COMMAND test_motor_firmware_sim)
  set_tests_properties(test_motor_firmware_sim PROPERTIES LABELS cpu)
  add_dependencies(cpu_tests test_motor_firmware_sim)
else()
  set(simavr_missing "simavr is missing: no sim_avr.h or libsimavr found (Debian: apt-get install libsimavr-dev, then reconfigure)")
  if(REMOTETOUCH_REQUIRE_ALL_TESTS)
    message(FATAL_ERROR "${simavr_missing}: test_motor_firmware_sim cannot run")
  endif()
  message(STATUS "${simavr_missing}; test_motor_firmware_sim will report a skip")
  add_test(NAME test_motor_firmware_sim COMMAND sh -c "echo 'test_motor_firmware_sim skipped: ${simavr_missing}'; exit 77")
  # Only here: the real test's exit status is Catch2's count of failed assertions.
  set_tests_properties(test_motor_firmware_sim PROPERTIES SKIP_RETURN_CODE 77)
endif()
