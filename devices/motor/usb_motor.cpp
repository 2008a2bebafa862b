#include "motor/usb_motor.h"

#include <iostream>
#include <stdexcept>

#include "motor/usb_link.h"

namespace rt::motor {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

std::string ms_text(milliseconds duration) { return std::to_string(duration.count()) + " ms"; }

void check_options(const UsbMotorOptions& options) {
  const std::pair<const char*, milliseconds> durations[] = {
      {"write_timeout", options.write_timeout}, {"reply_timeout", options.reply_timeout},
      {"ready_timeout", options.ready_timeout}, {"drain_quiet", options.drain_quiet},
      {"retry_initial", options.retry_initial}, {"retry_max", options.retry_max}};
  for (const auto& [name, duration] : durations) {
    if (duration.count() <= 0) {
      throw std::invalid_argument(std::string("UsbMotorOptions::") + name + " must be positive, not " +
                                  ms_text(duration));
    }
  }
  if (options.retry_initial > options.retry_max) {
    throw std::invalid_argument("UsbMotorOptions::retry_initial (" + ms_text(options.retry_initial) +
                                ") must not exceed retry_max (" + ms_text(options.retry_max) + ")");
  }
  if (options.baud == 0) throw std::invalid_argument("UsbMotorOptions::baud must be positive");
}

}  // namespace

struct UsbMotor::State {
  UsbMotorOptions options;
  usb::Context context;
  std::unique_ptr<UsbLink> link;  // after context: closed before libusb_exit
  Clock::time_point next_attempt{};
  milliseconds backoff{};
  std::string last_failure;
  bool drain_before_next = false;

  void log(const std::string& line) const { options.log(line); }
  MotorStatus ensure_connected(bool ignore_backoff);
  MotorStatus device_failure(int code, const std::string& error);
  MotorStatus exchange(const std::string& command, std::string* reply);
  MotorStatus command(const std::string& command, const std::string& expected_reply);
  // The failure for a reply that is not the expected one: ERR from the firmware, or garbage.
  MotorStatus rejected(const std::string& command, const std::string& reply, const std::string& expected_reply);
};

UsbMotor::UsbMotor(UsbMotorOptions options) : state_(std::make_unique<State>()) {
  check_options(options);
  if (!options.log) options.log = [](const std::string& line) { std::cerr << "[motor] " << line << '\n'; };
  state_->options = std::move(options);
  state_->backoff = state_->options.retry_initial;
  state_->context = usb::make_context();
}

UsbMotor::~UsbMotor() {
  // The board stops by itself at the pulse's deadline; this only makes it stop now.
  if (state_->link) {
    std::string ignored;
    state_->link->write_line("S", state_->options.write_timeout, &ignored);
  }
}

MotorStatus UsbMotor::connect() { return state_->ensure_connected(true); }

bool UsbMotor::connected() const { return state_->link != nullptr; }

std::string UsbMotor::firmware() const { return state_->link ? state_->link->firmware() : std::string(); }

MotorStatus UsbMotor::pulse(milliseconds duration, int strength) {
  if (std::string why = check_pulse(duration, strength); !why.empty()) return MotorStatus::failure(why);
  const std::string command = "P " + std::to_string(duration.count()) + " " + std::to_string(strength);
  // The firmware echoes the values it accepted, so a reply meant for another command is caught.
  return state_->command(command, "OK " + command);
}

MotorStatus UsbMotor::stop() { return state_->command("S", "OK S"); }

MotorStatus UsbMotor::query_version(std::string& version) {
  std::string reply;
  if (MotorStatus status = state_->exchange("V", &reply); !status) return status;
  if (reply.rfind("OK V ", 0) == 0 && reply.size() > 5) {
    version = reply.substr(5);
    return MotorStatus::success();
  }
  return state_->rejected("V", reply, "OK V <firmware> <protocol>");
}

MotorStatus UsbMotor::State::ensure_connected(bool ignore_backoff) {
  if (link) return MotorStatus::success();
  const auto now = Clock::now();
  if (!ignore_backoff && now < next_attempt) {
    return MotorStatus::failure("motor not connected (" + last_failure + "); next attempt in " +
                                ms_text(std::chrono::ceil<milliseconds>(next_attempt - now)));
  }
  auto opened = UsbLink::open(context.get(), options, [this](const std::string& line) { log(line); });
  if (auto* why = std::get_if<std::string>(&opened)) {
    last_failure = *why;
    next_attempt = now + backoff;
    log("cannot open the motor: " + *why + " (next attempt in " + ms_text(backoff) + ")");
    backoff = std::min(backoff * 2, options.retry_max);
    return MotorStatus::failure("motor not connected: " + *why);
  }
  link = std::move(std::get<std::unique_ptr<UsbLink>>(opened));
  backoff = options.retry_initial;
  drain_before_next = false;
  log("motor connected: " + link->where() + ", firmware " + link->firmware());
  return MotorStatus::success();
}

MotorStatus UsbMotor::State::device_failure(int code, const std::string& error) {
  const std::string where = link->where();
  // After an unplug, or a transfer error that leaves the pipe in an unknown state, only a
  // fresh open (which also resets the board) gives a known state again.
  if (code == LIBUSB_ERROR_NO_DEVICE || code == LIBUSB_ERROR_IO || code == LIBUSB_ERROR_PIPE) {
    link.reset();
    backoff = options.retry_initial;
    next_attempt = Clock::now();
    last_failure = code == LIBUSB_ERROR_NO_DEVICE ? "the board was unplugged" : "the last transfer failed";
    const std::string message =
        "motor " + where + (code == LIBUSB_ERROR_NO_DEVICE ? " was unplugged: " : " failed: ") + error +
        "; closed it, it is reopened on the next command";
    log(message);
    return MotorStatus::failure(message);
  }
  drain_before_next = true;
  return MotorStatus::failure("motor " + where + ": " + error);
}

MotorStatus UsbMotor::State::exchange(const std::string& command, std::string* reply) {
  if (MotorStatus status = ensure_connected(false); !status) return status;
  if (drain_before_next) {
    for (const ReplyLine& line : link->drain(options.drain_quiet)) {
      log(link->where() + ": dropped late input '" + quote_bytes(line.text) + "'");
    }
    drain_before_next = false;
  }
  std::string error;
  if (const int result = link->write_line(command, options.write_timeout, &error); result != 0) {
    return device_failure(result, error);
  }
  const auto deadline = Clock::now() + options.reply_timeout;
  for (;;) {
    ReplyLine line;
    const milliseconds remaining = std::chrono::ceil<milliseconds>(deadline - Clock::now());
    const int result = remaining.count() > 0 ? link->read_line(remaining, &line, &error) : LIBUSB_ERROR_TIMEOUT;
    if (result == LIBUSB_ERROR_TIMEOUT) {
      drain_before_next = true;
      return MotorStatus::failure("no reply from the motor (" + link->where() + ") to '" + command + "' within " +
                                  ms_text(options.reply_timeout));
    }
    if (result != 0) return device_failure(result, error);
    if (!line.error.empty()) {
      drain_before_next = true;
      return MotorStatus::failure("garbage from the motor (" + link->where() + ") in reply to '" + command +
                                  "': " + line.error + " in '" + quote_bytes(line.text) + "'");
    }
    if (line.text.rfind("READY ", 0) == 0) {
      // The board reset itself (watchdog, or a supply dip when the motor starts): the command
      // may be lost, in which case the wait ends in a timeout.
      log(link->where() + ": the board restarted ('" + quote_bytes(line.text) + "') while '" + command +
          "' waited for its reply");
      continue;
    }
    *reply = std::move(line.text);
    return MotorStatus::success();
  }
}

MotorStatus UsbMotor::State::command(const std::string& command, const std::string& expected_reply) {
  std::string reply;
  if (MotorStatus status = exchange(command, &reply); !status) return status;
  if (reply == expected_reply) return MotorStatus::success();
  return rejected(command, reply, expected_reply);
}

MotorStatus UsbMotor::State::rejected(const std::string& command, const std::string& reply,
                                      const std::string& expected_reply) {
  if (reply.rfind("ERR ", 0) == 0) {
    return MotorStatus::failure("the motor rejected '" + command + "': " + reply.substr(4));
  }
  drain_before_next = true;
  return MotorStatus::failure("unexpected reply from the motor (" + link->where() + ") to '" + command + "': '" +
                              quote_bytes(reply) + "' (expected '" + expected_reply + "' or 'ERR <reason>')");
}

}  // namespace rt::motor
