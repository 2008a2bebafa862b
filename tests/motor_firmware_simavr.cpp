// The motor firmware itself (the .elf the build makes for the Uno), run cycle by cycle in
// simavr: its UART, its 1 ms tick, its PWM and its watchdog, not only the parser. Built by
// tests/motor.cmake when simavr's library (Debian libsimavr-dev) is installed; without it the
// ctest of this name reports a skip that says so.
#include <catch2/catch.hpp>

#include <optional>
#include <string>

extern "C" {
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
}

namespace {

constexpr uint32_t kFrequency = 16'000'000;
constexpr double kCyclesPerMs = kFrequency / 1000.0;
// ATmega328P data-space addresses of the registers the motor output depends on.
constexpr int kDdrd = 0x2a, kPortd = 0x2b, kTccr2a = 0xb0, kOcr2b = 0xb4;
constexpr uint8_t kMotorPin = 1 << 3;   // PD3, Arduino D3, OC2B
constexpr uint8_t kCom2b1 = 1 << 5;

class SimulatedUno {
 public:
  SimulatedUno() {
    REQUIRE(elf_read_firmware(REMOTETOUCH_MOTOR_FIRMWARE_ELF, &firmware_) == 0);
    avr_ = avr_make_mcu_by_name("atmega328p");
    REQUIRE(avr_ != nullptr);
    avr_init(avr_);
    avr_->frequency = kFrequency;
    avr_load_firmware(avr_, &firmware_);
    // Neither echo the UART on the console nor sleep when the firmware polls it.
    uint32_t flags = 0;
    avr_ioctl(avr_, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~uint32_t(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
    avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), &on_uart_byte, this);
    uart_in_ = avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  }
  ~SimulatedUno() { avr_terminate(avr_); }
  SimulatedUno(const SimulatedUno&) = delete;
  SimulatedUno& operator=(const SimulatedUno&) = delete;

  double now_ms() const { return double(avr_->cycle) / kCyclesPerMs; }

  void send(const std::string& bytes) {
    for (const char byte : bytes) avr_raise_irq(uart_in_, uint8_t(byte));
  }

  void run_ms(double duration_ms) {
    const auto end = avr_cycle_count_t(double(avr_->cycle) + duration_ms * kCyclesPerMs);
    while (avr_->cycle < end) step();
  }

  // The next line the firmware prints, within `limit_ms` of simulated time.
  std::optional<std::string> next_line(double limit_ms) {
    const auto end = avr_cycle_count_t(double(avr_->cycle) + limit_ms * kCyclesPerMs);
    while (avr_->cycle < end) {
      if (const size_t eol = output_.find('\n'); eol != std::string::npos) {
        std::string line = output_.substr(0, eol);
        output_.erase(0, eol + 1);
        return line;
      }
      step();
    }
    return std::nullopt;
  }

  // The PWM duty on the motor pin: OCR2B while the compare output drives it, else the pin level.
  int motor_duty() const {
    const uint8_t* io = avr_->data;
    if (!(io[kDdrd] & kMotorPin)) return -1;  // not an output: the driver's input floats
    if (io[kTccr2a] & kCom2b1) return io[kOcr2b];
    return (io[kPortd] & kMotorPin) ? 255 : 0;
  }

  // Runs until the motor's duty is `duty`; returns when (ms), or nullopt if not by the limit.
  std::optional<double> run_until_duty(int duty, double limit_ms) {
    const auto end = avr_cycle_count_t(double(avr_->cycle) + limit_ms * kCyclesPerMs);
    while (avr_->cycle < end) {
      if (motor_duty() == duty) return now_ms();
      step();
    }
    return std::nullopt;
  }

  const std::string& pending_output() const { return output_; }

 private:
  static void on_uart_byte(avr_irq_t*, uint32_t value, void* self) {
    static_cast<SimulatedUno*>(self)->output_.push_back(char(value));
  }
  void step() {
    // Checked without Catch's REQUIRE, which would count millions of assertions.
    const int state = avr_run(avr_);
    if (state == cpu_Crashed || state == cpu_Done) FAIL("the firmware stopped in simavr (state " << state << ")");
  }

  elf_firmware_t firmware_{};
  avr_t* avr_ = nullptr;
  avr_irq_t* uart_in_ = nullptr;
  std::string output_;
};

}  // namespace

TEST_CASE("motor firmware in simavr: starts with the motor off and says READY", "[motor][firmware]") {
  SimulatedUno uno;
  const auto ready = uno.next_line(50);
  REQUIRE(ready);
  CHECK(*ready == "READY remotetouch-motor 1");
  CHECK(uno.motor_duty() == 0);
  // The hardware watchdog (250 ms) must not fire while the main loop runs: no second READY.
  uno.run_ms(600);
  CHECK(uno.pending_output().empty());
}

TEST_CASE("motor firmware in simavr: a pulse drives the PWM until its deadline", "[motor][firmware]") {
  SimulatedUno uno;
  REQUIRE(uno.next_line(50) == "READY remotetouch-motor 1");
  // The deadline counts 1 ms ticks from wherever the tick stands when the pulse starts, so a
  // pulse lasts between duration - 1 ms and duration: never longer than asked.
  for (const int duration : {1, 10, 1000}) {
    INFO("pulse of " << duration << " ms");
    uno.send("P " + std::to_string(duration) + " 200\n");
    const auto on_ms = uno.run_until_duty(200, 5);
    REQUIRE(on_ms);
    const auto off_ms = uno.run_until_duty(0, duration + 5);
    REQUIRE(off_ms);
    CHECK(*off_ms - *on_ms <= duration + 0.01);
    CHECK(*off_ms - *on_ms > duration - 1.01);
    CHECK(uno.next_line(5) == "OK P " + std::to_string(duration) + " 200");
  }
}

TEST_CASE("motor firmware in simavr: a new pulse or a stop ends the running one", "[motor][firmware]") {
  SimulatedUno uno;
  REQUIRE(uno.next_line(50) == "READY remotetouch-motor 1");
  SECTION("a new pulse replaces the running one") {
    uno.send("P 1000 50\n");
    REQUIRE(uno.next_line(20) == "OK P 1000 50");
    uno.run_ms(10);
    uno.send("P 20 90\n");
    const auto replaced_ms = uno.run_until_duty(90, 5);
    REQUIRE(replaced_ms);
    const auto off_ms = uno.run_until_duty(0, 100);
    REQUIRE(off_ms);
    CHECK(*off_ms - *replaced_ms == Approx(20).margin(1.01));
    CHECK(uno.next_line(1) == "OK P 20 90");
  }
  SECTION("stop ends it at once") {
    uno.send("P 1000 255\n");
    REQUIRE(uno.next_line(20) == "OK P 1000 255");
    CHECK(uno.motor_duty() == 255);
    uno.send("S\n");
    REQUIRE(uno.next_line(20) == "OK S");
    CHECK(uno.motor_duty() == 0);
  }
}

TEST_CASE("motor firmware in simavr: bad input is rejected and does not move the motor", "[motor][firmware]") {
  SimulatedUno uno;
  REQUIRE(uno.next_line(50) == "READY remotetouch-motor 1");
  uno.send("P 0 5\n");
  CHECK(uno.next_line(20) == "ERR duration 0 ms out of range 1..1000");
  uno.send("P 10 256\n");
  CHECK(uno.next_line(20) == "ERR strength 256 out of range 1..255");
  uno.send(std::string("P 10\x01 20\n"));
  CHECK(uno.next_line(20) == "ERR byte 0x01 is not printable ASCII");
  uno.send(std::string(40, '9') + "\n");
  CHECK(uno.next_line(20) == "ERR line longer than 32 bytes");
  CHECK(uno.motor_duty() == 0);
  uno.send("V\n");
  CHECK(uno.next_line(20) == "OK V remotetouch-motor 1");
}
