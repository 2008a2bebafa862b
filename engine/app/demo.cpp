// `remotetouch demo`: the main job, both sites of a scene as two processes over loopback
// (two_site_demo.cpp runs it). The image-based-model, hand and touch options go to both sites.
#include "app/command.h"
#include "app/option_groups.h"
#include "app/two_site_demo.h"

namespace rt::app {
namespace {

class DemoCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    command_ = parent.add_subcommand("demo", "Run the main job: both sites of a scene as two processes over loopback");
    add_run_options(*command_, options_.run, "out/demo");
    command_->add_option("--scene", options_.scene, "Scene name under assets/scenes/, or a scene file")->capture_default_str();
    frames_ = add_frames_option(*command_, options_.run, 1, "the scene's own count");
    frames_->description("Scene frames to play");
    options_.run.width = 640;
    options_.run.height = 360;
    add_size_options(*command_, options_.run, "Portrait and display", 16, 4096);
    command_->add_option("--time-scale", options_.time_scale,
                         "Scene seconds per wall-clock second (below 1 plays the scene slower, for slow devices)")
        ->check(CLI::Range(0.01, 10.0))
        ->default_str("1 on a GPU, 0.25 on a CPU Vulkan driver");
    command_->add_option("--resolution-scale", options_.resolution_scale, "Camera resolution scale")
        ->check(CLI::Range(0.01, 1.0))
        ->default_str("the scene's");
    CLI::Option* disconnect = command_->add_option("--disconnect-after-ms", disconnect_after_ms_,
                                                   "Fault injection: cut the link once, this long after the sites connect");
    // An outage without a cut would do nothing: refuse it rather than run a fault-free demo.
    command_->add_option("--outage-ms", options_.outage_ms,
                         "Fault injection: with --disconnect-after-ms, the link stays silent this long after the cut")
        ->check(CLI::Range(0, 60000))
        ->needs(disconnect);
    command_->add_option("--delay-ms", options_.delay_ms, "Fault injection: delay every record")->check(CLI::Range(0, 10000));
    command_->add_option("--jitter-ms", options_.jitter_ms, "Fault injection: extra random delay per record")
        ->check(CLI::Range(0, 10000));
    command_->add_option("--loss", options_.loss, "Fault injection: probability that a record is lost, which cuts the link there (as a TCP connection that loses data dies)")->check(CLI::Range(0.0, 0.9));
    command_->add_option("--transport", options_.transport,
                         "direct: everything over the session; webrtc: the session sets up a WebRTC call that carries "
                         "the portraits as H.264 video and the rest on sealed data channels (site --transport)")
        ->check(CLI::IsMember({"direct", "webrtc"}))
        ->capture_default_str();
    command_->add_option("--packet-loss", options_.packet_loss,
                         "With --transport webrtc: each site's video loses this fraction of its RTP packets at random "
                         "(GStreamer's netsim; retransmission and keyframes repair it)")
        ->check(CLI::Range(0.0, 0.5));
    command_->add_option("--replay-a", options_.replay_a, "Site A plays this recording instead of the scene (site --replay)");
    command_->add_option("--replay-b", options_.replay_b, "Site B plays this recording instead of the scene (site --replay)");
    command_->add_option("--display", options_.display,
                         "Each site's window: window (shown, and the frames written for the report), headless, both, "
                         "or auto: a window where a display is present")
        ->check(CLI::IsMember({"window", "headless", "both", "auto"}))
        ->capture_default_str();
    command_->add_option("--present-mode", options_.present_mode, "fifo, or mailbox where the device offers it")
        ->check(CLI::IsMember({"fifo", "mailbox"}))
        ->capture_default_str();
    command_->add_option("--sound", options_.sound,
                         "simulated: each simulated user says a sentence, the scene's room echoes it (site_X/audio.wav "
                         "holds what each loudspeaker played); none: a silent call")
        ->check(CLI::IsMember({"simulated", "none"}))
        ->capture_default_str();
    command_->add_flag("--noise-suppression", options_.noise_suppression, "Each site's voice noise suppression (webrtcdsp)");
    command_->add_flag("--gain-control", options_.gain_control, "Each site's voice gain control (webrtcdsp)");
    command_->add_flag("--no-lip-sync", options_.no_lip_sync, "Each site plays the far voice as it comes, not held to the far portrait");
    add_inspection_options(*command_, options_.run);  // forwarded to both sites
    ibr_ = add_ibr_options(*command_);
    quality_.add_to(*command_);
    hand_ = add_hand_options(*command_);
    touch_ = add_touch_options(*command_);
    return command_;
  }

  void check() override {
    options_.frames_given = frames_->count() > 0;
    if (disconnect_after_ms_ >= 0) options_.disconnect_after_ms = disconnect_after_ms_;
    // The fault proxy sits on the session's TCP connection, which a WebRTC call only sets up.
    if (options_.transport == "webrtc" &&
        (disconnect_after_ms_ >= 0 || options_.delay_ms > 0 || options_.jitter_ms > 0 || options_.loss > 0))
      throw CLI::ValidationError("--transport webrtc",
                                 "the fault options act on the direct session's TCP connection, not on a WebRTC call");
    if (options_.packet_loss >= 0 && options_.transport != "webrtc")
      throw CLI::ValidationError("--packet-loss", "simulates loss on a WebRTC call's video: it needs --transport webrtc");
    // The video tracks are 4:2:0: both sides even.
    if (options_.transport == "webrtc" && (options_.run.width % 2 || options_.run.height % 2))
      throw CLI::ValidationError("--transport webrtc", "--width and --height must be even (the video is 4:2:0)");
    options_.ibr.width = options_.run.width;
    options_.ibr.height = options_.run.height;
    options_.quality = quality_.apply(options_.ibr, options_.resolution_scale, command_->count("--resolution-scale") > 0);
    options_.quality_arguments = quality_.arguments();
    ibr_.apply(options_.ibr);
    hand_.apply(options_.hand);
    touch_.apply(options_.touch);
  }
  int run() override { return run_two_site_demo(options_); }

 private:
  CLI::App* command_ = nullptr;
  CLI::Option* frames_ = nullptr;
  DemoOptions options_;
  int disconnect_after_ms_ = -1;
  IbrOptions ibr_;
  QualityOptions quality_;
  HandOptions hand_;
  TouchOptions touch_;
};

}  // namespace

std::unique_ptr<Command> make_demo_command() { return std::make_unique<DemoCommand>(); }

}  // namespace rt::app
