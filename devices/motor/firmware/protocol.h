#ifndef REMOTETOUCH_MOTOR_PROTOCOL_H
#define REMOTETOUCH_MOTOR_PROTOCOL_H
/*
 * The motor's line protocol, shared by the firmware and the host. Plain C without AVR headers
 * so that the host tests compile the very parser the board runs, and the host driver checks
 * its arguments against the same bounds before anything goes on the wire.
 *
 * Host to board, one command per line ('\n' or '\r' ends a line, fields split by spaces):
 *   P <duration_ms> <strength>   pulse: run the motor for duration_ms at PWM duty strength/255
 *   S                            stop now
 *   V                            version
 * Board to host, one reply line per command:
 *   OK P <duration_ms> <strength> | OK S | OK V remotetouch-motor <protocol>
 *   ERR <what is wrong>
 * and, once after every reset:  READY remotetouch-motor <protocol>
 *
 * Every value out of its bounds is rejected with ERR, never clamped.
 */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MOTOR_FIRMWARE_NAME "remotetouch-motor"
#define MOTOR_PROTOCOL_VERSION 1

/* A pulse is also the firmware's dead-man watchdog: the motor runs only until the last
 * pulse's deadline, so a host that stops sending stops the motor within this bound. */
#define MOTOR_DURATION_MIN_MS 1u
#define MOTOR_DURATION_MAX_MS 1000u
/* Strength 0 would be a pulse that does nothing: a host bug, so it is rejected; S stops. */
#define MOTOR_STRENGTH_MIN 1u
#define MOTOR_STRENGTH_MAX 255u

/* Longest command line, terminator excluded. "P 1000 255" is 10 bytes; the margin lets a
 * too-large number be reported as out of range rather than as an overlong line. */
#define MOTOR_LINE_MAX 32u
/* Longest line the board sends, terminator excluded. */
#define MOTOR_REPLY_MAX 63u

typedef enum {
  MOTOR_COMMAND_NONE,     /* blank line: no reply */
  MOTOR_COMMAND_PULSE,
  MOTOR_COMMAND_STOP,
  MOTOR_COMMAND_VERSION,
  MOTOR_COMMAND_REJECTED  /* reply with the error */
} motor_command_kind;

typedef enum {
  MOTOR_ERROR_NONE,
  MOTOR_ERROR_UNKNOWN_COMMAND,
  MOTOR_ERROR_SYNTAX,
  MOTOR_ERROR_NUMBER_TOO_LONG,
  MOTOR_ERROR_DURATION_RANGE,
  MOTOR_ERROR_STRENGTH_RANGE,
  MOTOR_ERROR_LINE_TOO_LONG,
  MOTOR_ERROR_BAD_BYTE,
  MOTOR_ERROR_OVERRUN
} motor_error;

typedef struct {
  motor_command_kind kind;
  uint16_t duration_ms;
  uint8_t strength;
  motor_error error;
  uint32_t bad_value; /* the number out of range, or the byte that is not allowed */
  char letter;        /* the command a syntax error belongs to */
  char token[9];      /* the start of an unknown command, for its error line */
} motor_command;

/* Assembles bytes into lines. A line that grows past MOTOR_LINE_MAX, holds a byte outside
 * printable ASCII, or loses bytes to a receive overrun is remembered as bad and rejected
 * once its terminator arrives, so the parser resynchronises at every line end. */
typedef struct {
  char line[MOTOR_LINE_MAX];
  uint8_t length;
  motor_error pending_error;
  uint8_t bad_byte;
} motor_parser;

void motor_parser_reset(motor_parser* parser);

/* Returns 1 when `byte` ended a line that needs a reply (written to *command), else 0. */
int motor_parser_feed(motor_parser* parser, uint8_t byte, motor_command* command);

/* The UART lost bytes of the line being received: reject that line when it ends. */
void motor_parser_mark_overrun(motor_parser* parser);

/* Parses one complete line (no terminator). */
motor_command motor_parse_line(const char* line, size_t length);

/* Writes the reply line for a command (no terminator, NUL-terminated); returns its length,
 * at most MOTOR_REPLY_MAX, or 0 for MOTOR_COMMAND_NONE. capacity must exceed MOTOR_REPLY_MAX. */
size_t motor_format_reply(const motor_command* command, char* out, size_t capacity);

/* The line printed once at start. */
size_t motor_format_ready(char* out, size_t capacity);

/* 1 when the pulse values are inside the protocol's bounds. */
int motor_pulse_in_bounds(uint32_t duration_ms, uint32_t strength);

#ifdef __cplusplus
}
#endif

#endif
