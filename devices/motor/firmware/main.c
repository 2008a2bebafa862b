/*
 * RemoteTouch motor firmware for the Arduino Uno (ATmega328P, 16 MHz).
 *
 * The motor driver's input is on Arduino pin D3 (PD3, OC2B): Timer2 drives it with PWM at
 * 16 MHz / 8 / 256 = 7.8 kHz, above the audible whine of slower PWM. Timer0 ticks every
 * millisecond and ends each pulse in its interrupt, so a pulse ends on time even while the
 * main loop is busy writing a reply. Commands arrive on the UART (the Uno's 16U2 bridges it to
 * USB CDC-ACM) at 115200 8N1; the protocol is in protocol.h.
 *
 * Two watchdogs:
 *  - commands: every pulse is at most MOTOR_DURATION_MAX_MS long and the motor stops at its
 *    deadline, so when the host stops sending, the motor stops by itself;
 *  - hangs: the hardware watchdog resets the chip if the main loop stalls for 250 ms; the
 *    reset turns PD3 into an input (the driver board needs a pull-down on its input) and the
 *    firmware starts again with the motor off and prints READY.
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/wdt.h>
#include <stdint.h>
#include <util/atomic.h>

/* 115200 baud from 16 MHz is 2.1 % fast with U2X (UBRR 16), as on every Uno sketch; the
 * 16U2 bridge uses the same divisor, so both ends agree. setbaud's default 2 % would warn. */
#define BAUD 115200
#define BAUD_TOL 3
#include <util/setbaud.h>

#include "protocol.h"

#define MOTOR_PIN PD3
#define RX_BUFFER_SIZE 64u /* a power of two: the index wraps with a mask */

static volatile uint16_t pulse_remaining_ms;
static volatile uint8_t rx_buffer[RX_BUFFER_SIZE];
static volatile uint8_t rx_head, rx_tail;
static volatile uint8_t rx_lost; /* bytes dropped (buffer full, UART overrun, framing error) */

/* After a watchdog reset the watchdog stays enabled with its shortest timeout; it must be
 * switched off before main() or the chip would reset again during start-up. */
void disable_watchdog_at_reset(void) __attribute__((naked, used, section(".init3")));
void disable_watchdog_at_reset(void) {
  MCUSR = 0;
  wdt_disable();
}

static void motor_off(void) {
  TCCR2A &= (uint8_t)~_BV(COM2B1);
  PORTD &= (uint8_t)~_BV(MOTOR_PIN);
}

static void motor_on(uint8_t duty) {
  OCR2B = duty;
  TCCR2A |= _BV(COM2B1);
}

static void motor_init(void) {
  PORTD &= (uint8_t)~_BV(MOTOR_PIN);
  DDRD |= _BV(MOTOR_PIN);
  TCCR2A = _BV(WGM21) | _BV(WGM20); /* fast PWM, output disconnected until a pulse */
  TCCR2B = _BV(CS21);
}

static void tick_init(void) {
  TCCR0A = _BV(WGM01); /* CTC: 16 MHz / 64 / 250 = 1 kHz */
  TCCR0B = _BV(CS01) | _BV(CS00);
  OCR0A = 249;
  TIMSK0 = _BV(OCIE0A);
}

ISR(TIMER0_COMPA_vect) {
  if (pulse_remaining_ms != 0 && --pulse_remaining_ms == 0) motor_off();
}

static void uart_init(void) {
  UBRR0H = UBRRH_VALUE;
  UBRR0L = UBRRL_VALUE;
#if USE_2X
  UCSR0A = _BV(U2X0);
#else
  UCSR0A = 0;
#endif
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00); /* 8N1 */
  UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
}

ISR(USART_RX_vect) {
  const uint8_t status = UCSR0A;
  const uint8_t byte = UDR0;
  const uint8_t next = (uint8_t)((rx_head + 1u) & (RX_BUFFER_SIZE - 1u));
  if ((status & (_BV(FE0) | _BV(DOR0))) || next == rx_tail) {
    rx_lost = 1;
    return;
  }
  rx_buffer[rx_head] = byte;
  rx_head = next;
}

static int uart_read(uint8_t* byte) {
  int got = 0;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    if (rx_tail != rx_head) {
      *byte = rx_buffer[rx_tail];
      rx_tail = (uint8_t)((rx_tail + 1u) & (RX_BUFFER_SIZE - 1u));
      got = 1;
    }
  }
  return got;
}

static int uart_take_lost(void) {
  int lost;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    lost = rx_lost;
    rx_lost = 0;
  }
  return lost;
}

/* A reply is at most 64 bytes, about 6 ms at 115200 baud: far inside the watchdog's 250 ms. */
static void uart_write_line(const char* text, size_t length) {
  for (size_t i = 0; i < length; ++i) {
    loop_until_bit_is_set(UCSR0A, UDRE0);
    UDR0 = (uint8_t)text[i];
  }
  loop_until_bit_is_set(UCSR0A, UDRE0);
  UDR0 = '\n';
}

static void execute(const motor_command* command) {
  switch (command->kind) {
    case MOTOR_COMMAND_PULSE:
      ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        /* A new pulse replaces the running one: the host holds the motor on by repeating. */
        pulse_remaining_ms = command->duration_ms;
        motor_on(command->strength);
      }
      break;
    case MOTOR_COMMAND_STOP:
      ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        pulse_remaining_ms = 0;
        motor_off();
      }
      break;
    default:
      break;
  }
}

int main(void) {
  motor_init();
  tick_init();
  uart_init();
  wdt_enable(WDTO_250MS);
  sei();

  char reply[MOTOR_REPLY_MAX + 1];
  uart_write_line(reply, motor_format_ready(reply, sizeof reply));

  motor_parser parser;
  motor_parser_reset(&parser);
  for (;;) {
    wdt_reset();
    if (uart_take_lost()) motor_parser_mark_overrun(&parser);
    uint8_t byte;
    motor_command command;
    while (uart_read(&byte)) {
      if (motor_parser_feed(&parser, byte, &command)) {
        execute(&command);
        uart_write_line(reply, motor_format_reply(&command, reply, sizeof reply));
        wdt_reset();
      }
    }
  }
}
