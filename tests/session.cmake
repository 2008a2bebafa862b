# The two-site session (engine/app/site_runner.h, `remotetouch demo` and `remotetouch site`):
# two processes over loopback, tiny sizes, only the frames each case needs (clap: the palms meet
# at about 2.6 s and part at 3.4 s of scene time).
set(rt $<TARGET_FILE:remotetouch>)
set(session_demo ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_demo.sh)
add_test(NAME session_demo_clap COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-clap clap 115 1)
add_test(NAME session_demo_av_marker
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_demo_av_marker.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-av-marker)
# A fist bump: one touch per site named "fist" at its start, its motor and the other site.
add_test(NAME session_demo_fist_bump COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-fist-bump fist-bump 115 1)
set_tests_properties(session_demo_fist_bump PROPERTIES ENVIRONMENT GESTURE=fist)
add_test(NAME session_demo_miss COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-miss miss 115 0)
# A scene asking for the seat: no eye search, the seat's head position from the start.
add_test(NAME session_demo_seat
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_seat.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-seat
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/clap-seat.json)
add_test(NAME session_demo_wave COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-wave wave 90 0)
# The link cut mid-run (before the touch) through the fault proxy: the connector reconnects, the
# run finishes, the clap still gives one touch per site.
add_test(NAME session_demo_disconnect
         COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-disconnect clap 115 1 --disconnect-after-ms 1200)
# The link cut and kept silent for 0.6 s: both displays keep running and show the remote side
# lost, the connector gets back in before the scene's end, the run finishes. The whole of wave
# (5 s): a connection attempt caught by the silence waits out its 2-s handshake timeout first.
add_test(NAME session_demo_outage
         COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-outage wave 150 0 --disconnect-after-ms 400 --outage-ms 600)
# A slow, lossy link (40 ms delay, 20 ms jitter, 2 % of records lost, each loss a cut link as TCP
# would give it): still one touch per site.
# Without sound: the fault proxy cuts the link at a lost record, and the voice's fifty records a
# second would cut it twice as often as the touch path this test is about.
add_test(NAME session_demo_lossy
         COMMAND ${session_demo} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-lossy clap 115 1 --delay-ms 40 --jitter-ms 20 --loss 0.02
                 --sound none)
# The same scene over a WebRTC call set up through the session, then over the direct session: the
# same touches, and the hand at the glass within 1 dB (the two sites' mean).
add_test(NAME session_demo_webrtc
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_demo_webrtc.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-webrtc clap 115 1)
add_test(NAME session_demo_webrtc_miss
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_demo_webrtc.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-webrtc-miss miss 115 0)
# The clap over a WebRTC call whose video loses 2 % of its packets (netsim): the same touches, each
# touch event received once, the loss seen and each broken track recovered within 500 ms.
add_test(NAME session_demo_webrtc_loss
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_demo_webrtc_loss.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-webrtc-loss clap 115 1)
# A site stopped by SIGTERM mid-run writes its metrics; SIGINT while waiting for a peer ends the wait.
add_test(NAME session_site_signal
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_signal.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-signal)
set_tests_properties(session_site_signal PROPERTIES TIMEOUT 300)
# A wrong key: both sites refuse the handshake, the connector says why at each attempt and tries
# again until its connect timeout; both give up cleanly, saying why.
add_test(NAME session_site_wrong_key
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_wrong_key.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-wrong-key)
# A fake listener (an older release's) refuses the connecting site once: the site says why, keeps
# trying, and the real listener, up later on that port, gets the call.
add_test(NAME session_site_refused_then_listener
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_refused_then_listener.sh ${rt}
                 ${CMAKE_BINARY_DIR}/test-out/session-refused-then-listener)
add_cli_test(session_site_bad_config 1 "remotetouch: error: .*site_config_bad\\.json: unknown field 'peers'"
             ${rt} site --config ${CMAKE_CURRENT_SOURCE_DIR}/data/site_config_bad.json --out ${CMAKE_BINARY_DIR}/test-out/site-bad-config)
set_tests_properties(session_demo_clap session_demo_av_marker session_demo_fist_bump session_demo_miss session_demo_seat session_demo_wave session_demo_disconnect session_demo_outage session_demo_lossy
                     session_demo_webrtc session_demo_webrtc_miss session_demo_webrtc_loss
                     session_site_wrong_key session_site_refused_then_listener
                     PROPERTIES TIMEOUT 300
                     # Two site processes each on a real-time scene clock, sharing the CPU with a CPU
                     # Vulkan driver: they run alone. Beside other lavapipe tests under ctest -j2, the
                     # touch loop got 40 % of its ticks and a clap went undetected.
                     RUN_SERIAL TRUE)
add_cli_test(session_demo_unknown_device 1 "no Vulkan device fits.*site A ended"
             ${rt} demo --frames 2 --width 32 --height 18 --device no-such-gpu --out ${CMAKE_BINARY_DIR}/test-out/session-no-device)
add_cli_test(session_site_needs_key 1 "remotetouch: error: a site needs --key-file"
             ${rt} site --site A --out ${CMAKE_BINARY_DIR}/test-out/site-no-key)
# Key files: keygen makes one owner-only and never overwrites it; a site refuses one others can read.
add_test(NAME session_keygen
         COMMAND ${CMAKE_COMMAND} -E rm -f ${CMAKE_BINARY_DIR}/test-out/keygen/site.key)
add_cli_test(session_keygen_writes 0 "wrote a new session key to .*keygen/site.key \\(mode 0600\\)"
             ${rt} keygen ${CMAKE_BINARY_DIR}/test-out/keygen/site.key)
add_cli_test(session_keygen_never_overwrites 1 "cannot create the key file .*keygen/site.key: File exists \\(a key file is never overwritten"
             ${rt} keygen ${CMAKE_BINARY_DIR}/test-out/keygen/site.key)
set_tests_properties(session_keygen PROPERTIES FIXTURES_SETUP keygen)
set_tests_properties(session_keygen_writes PROPERTIES FIXTURES_REQUIRED keygen FIXTURES_SETUP keygen_written)
set_tests_properties(session_keygen_never_overwrites PROPERTIES FIXTURES_REQUIRED keygen_written)
file(WRITE ${CMAKE_BINARY_DIR}/test-out/keygen/open.key "0000000000000000000000000000000000000000000000000000000000000042\n")
file(CHMOD ${CMAKE_BINARY_DIR}/test-out/keygen/open.key PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)
add_cli_test(session_site_open_key_file 1 "open.key is open to the group or others \\(mode 0644\\): chmod 600"
             ${rt} site --site A --key-file ${CMAKE_BINARY_DIR}/test-out/keygen/open.key
                   --width 32 --height 18 --resolution-scale 0.05 --out ${CMAKE_BINARY_DIR}/test-out/site-open-key)
# (Owner-only, so that the contents are what is refused: the permissions are checked first.)
file(WRITE ${CMAKE_BINARY_DIR}/test-out/keygen/bad.key "{\"not\": \"a key\"}\n")
file(CHMOD ${CMAKE_BINARY_DIR}/test-out/keygen/bad.key PERMISSIONS OWNER_READ OWNER_WRITE)
add_cli_test(session_site_bad_key_file 1 "remotetouch: error: .*bad\\.key: session key: expected 64 hex digits"
             ${rt} site --site A --key-file ${CMAKE_BINARY_DIR}/test-out/keygen/bad.key
                   --width 32 --height 18 --resolution-scale 0.05 --out ${CMAKE_BINARY_DIR}/test-out/site-bad-key)
# The WebRTC call's servers: a bad --turn is refused naming what is wrong, without its password;
# the call's options on the direct transport are refused (the key is a test's, not a secret).
file(WRITE ${CMAKE_BINARY_DIR}/test-out/keygen/call.key "8f3a1c9e47b2d06f5e18a7c3b94d2e60f1a8c5b7e3d9024a6c1f8e5b3a7d9c02\n")
file(CHMOD ${CMAKE_BINARY_DIR}/test-out/keygen/call.key PERMISSIONS OWNER_READ OWNER_WRITE)
add_cli_test(session_site_bad_turn 1 "remotetouch: error: --turn 'turn://alice:\\*\\*\\*@127.0.0.1:99999': port 99999 is not from 1 to 65535"
             ${rt} site --site A --key-file ${CMAKE_BINARY_DIR}/test-out/keygen/call.key --transport webrtc
                   --turn turn://alice:hunter2@127.0.0.1:99999
                   --width 32 --height 18 --resolution-scale 0.05 --out ${CMAKE_BINARY_DIR}/test-out/site-bad-turn)
add_cli_test(session_site_stun_needs_webrtc 1 "remotetouch: error: --stun, --turn.*need --transport webrtc"
             ${rt} site --site A --key-file ${CMAKE_BINARY_DIR}/test-out/keygen/call.key --stun stun://127.0.0.1
                   --width 32 --height 18 --resolution-scale 0.05 --out ${CMAKE_BINARY_DIR}/test-out/site-stun-direct)
add_cli_test(session_site_janus_ca_needs_wss 1 "remotetouch: error: --janus-ca names the authorities of a wss:// Janus; ws://127.0.0.1:8188 is not one"
             ${rt} site --site A --key-file ${CMAKE_BINARY_DIR}/test-out/keygen/call.key --transport webrtc
                   --janus ws://127.0.0.1:8188 --room 5 --janus-ca ${CMAKE_BINARY_DIR}/test-out/keygen/call.key
                   --width 32 --height 18 --resolution-scale 0.05 --out ${CMAKE_BINARY_DIR}/test-out/site-janus-ca-ws)
# A site replaying a recording (`site --replay`): site B of clap recorded once by `simulate`
# (tiny: 115 frames at a tenth of the cameras' resolution, ground truth at the display's size),
# then played against a simulated site A; an image unreadable mid-run; bad inputs.
set(replay_recording ${CMAKE_BINARY_DIR}/test-out/session-replay-recording)
add_test(NAME session_replay_record
         COMMAND ${rt} simulate --scene clap --site B --frames 115 --resolution-scale 0.1 --gt-width 96 --gt-height 54
                 --out ${replay_recording})
set_tests_properties(session_replay_record PROPERTIES FIXTURES_SETUP replay_recording TIMEOUT 300)
set(session_replay ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_replay.sh)
foreach(mode session broken-png bad-inputs)
  add_test(NAME session_site_replay_${mode}
           COMMAND ${session_replay} ${rt} ${CMAKE_BINARY_DIR}/test-out/session-replay-${mode} ${replay_recording} ${mode})
  set_tests_properties(session_site_replay_${mode} PROPERTIES FIXTURES_REQUIRED replay_recording TIMEOUT 300)
endforeach()
set_tests_properties(session_site_replay_session session_site_replay_broken-png PROPERTIES RUN_SERIAL TRUE)
# A site's window on a virtual X server: the screen shows the composite written for its frame,
# F1 a debug view, S a screenshot, Esc a clean end.
add_test(NAME session_site_window
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_window.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-window)
set_tests_properties(session_site_window PROPERTIES TIMEOUT 300 RUN_SERIAL TRUE)
# A two-minute soak (scripts/soak): a clap every 6 s through a slow, jittery link that is cut now
# and then; each site's memory flat after warm-up and one touch per cycle. Alone, as a site pair
# takes both cores.
add_test(NAME soak_two_minutes
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/soak.py --binary ${rt} 2 --out ${CMAKE_BINARY_DIR}/test-out/soak --check)
set_tests_properties(soak_two_minutes PROPERTIES LABELS soak RUN_SERIAL TRUE TIMEOUT 600)
# A flood of garbage connections at a listening site: memory, log and the real peer's way in.
add_test(NAME session_site_flood
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/cli/site_under_flood.py ${rt} ${CMAKE_BINARY_DIR}/test-out/site-flood)
set_tests_properties(session_site_flood PROPERTIES RUN_SERIAL TRUE TIMEOUT 300)
# Two sites by hand as the README shows them: the defaults, one site's end, an unreachable peer.
add_test(NAME session_site_by_hand
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/session_by_hand.sh ${rt} ${CMAKE_BINARY_DIR}/test-out/session-by-hand)
set_tests_properties(session_site_by_hand PROPERTIES TIMEOUT 300 RUN_SERIAL TRUE)
# Every command line the README shows, run as a user would (shortened), and every command its
# table names: a documented command, option or output file that is gone fails here.
add_test(NAME readme_commands
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/cli/readme_commands.py ${CMAKE_SOURCE_DIR}/README.md ${rt}
                 ${CMAKE_BINARY_DIR}/test-out/readme-commands)
set_tests_properties(readme_commands PROPERTIES TIMEOUT 300 RUN_SERIAL TRUE)
# A config that is not there: the file and the reason.
add_cli_test(session_site_missing_config 1 "remotetouch: error: cannot open '[^']*no-such-config\\.json': No such file or directory"
             ${rt} site --config no-such-config.json --out ${CMAKE_BINARY_DIR}/test-out/site-missing-config)
# The touch knobs refuse what makes no sense, on the command line and in a config.
add_cli_test(session_site_bad_motor_latency 105 "--motor-latency-ms: Value -5 not in range"
             ${rt} site --motor-latency-ms -5)
add_cli_test(session_site_bad_contact_prediction 105 "--contact-prediction: maybe not in \\{on,off\\}"
             ${rt} demo --contact-prediction maybe)
add_cli_test(session_site_bad_touch_config 1
             "site_config_bad_touch\\.json: 'touch': field 'motor_latency_ms' must be a number in \\[0, 1000\\], is -5"
             ${rt} site --config ${CMAKE_CURRENT_SOURCE_DIR}/data/site_config_bad_touch.json
             --out ${CMAKE_BINARY_DIR}/test-out/site-bad-touch-config)
